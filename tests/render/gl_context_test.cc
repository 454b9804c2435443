// Tests of the headless GL contexts: back-end names, an OSMesa context with a GL_RENDERER, and
// the one-platform-per-process rule (MuJoCo binds GL functions once per process).

#include "render/gl_context.h"

#include <gtest/gtest.h>

#include "core/errors.h"

namespace hribench::render {
namespace {

TEST(GlContextTest, BackendNamesRoundTrip) {
  for (Backend b : {Backend::kOsmesa, Backend::kEgl, Backend::kNone}) {
    EXPECT_EQ(parse_backend(to_string(b)), b);
  }
}

TEST(GlContextTest, UnknownBackendIsAnInputError) {
  try {
    parse_backend("vulkan");
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "--backend: expected one of osmesa, egl, none, got 'vulkan'");
  }
}

TEST(GlContextTest, OsmesaContextReportsItsRenderer) {
  std::unique_ptr<GlContext> context = make_gl_context(Backend::kOsmesa);
  ASSERT_NE(context, nullptr);
  EXPECT_EQ(context->backend(), Backend::kOsmesa);
  EXPECT_FALSE(context->gl_renderer().empty());
  EXPECT_FALSE(context->gl_version().empty());
  EXPECT_EQ(loaded_gl_platform(), Backend::kOsmesa);
  // Two contexts can live side by side and be made current in turn.
  std::unique_ptr<GlContext> second = make_gl_context(Backend::kOsmesa);
  second->make_current();
  context->make_current();
}

TEST(GlContextTest, TheOtherPlatformIsRefusedOnceOneIsLoaded) {
  std::unique_ptr<GlContext> context = make_gl_context(Backend::kOsmesa);
  try {
    make_gl_context(Backend::kEgl);
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(),
                 "egl: no usable GL context: this process already renders through osmesa "
                 "(MuJoCo binds GL functions once per process; use one back end)");
  }
}

}  // namespace
}  // namespace hribench::render
