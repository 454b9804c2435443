#pragma once
// A GoogleTest fixture holding the default scene: model::build(SceneSpec::Default()) and one
// sim::Data made from it (reset to the start pose, human posed, mj_forward done). Both are
// made in SetUp while MuJoCo warnings are recorded, and the mjData is watched, so a test fails
// on any MuJoCo warning from building or stepping the scene (see mujoco_fixture.h).
//
// Usage:
//   using SceneTest = hribench::testing::DefaultScene;
//   TEST_F(SceneTest, Something) { sim::step(model_, data_); ... }

#include "model/model.h"
#include "sim/data.h"
#include "support/mujoco_fixture.h"

namespace hribench::testing {

class DefaultScene : public MujocoTest {
 protected:
  void SetUp() override {
    MujocoTest::SetUp();
    model_ = model::build(model::SceneSpec::Default());
    data_ = sim::make_data(model_);
    Watch(data_.mj.get());
  }

  model::Model model_;
  sim::Data data_;
};

}  // namespace hribench::testing
