#include "policy/registry.h"

#include <gtest/gtest.h>

#include "core/errors.h"
#include "policy/builtin.h"

namespace hribench::policy {
namespace {

TEST(PolicyRef, ParsesNamesSchemesAndOptions) {
  PolicyRef a = parse_policy_ref("random?seed=3&space=joint_pos");
  EXPECT_EQ(a.name, "random");
  EXPECT_EQ(a.address, "");
  EXPECT_EQ(a.options.at("seed"), "3");
  EXPECT_EQ(a.options.at("space"), "joint_pos");
  PolicyRef b = parse_policy_ref("openpi://localhost:8000?replan=5");
  EXPECT_EQ(b.name, "openpi");
  EXPECT_EQ(b.address, "localhost:8000");
  EXPECT_EQ(b.options.at("replan"), "5");
  try {
    parse_policy_ref("random?seed");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "policy random: expected options as key=value, got 'seed'");
  }
  EXPECT_THROW(parse_policy_ref(""), core::InputError);
}

TEST(Registry, BuiltinsByName) {
  const std::vector<std::string> names = policy_names();
  EXPECT_NE(std::find(names.begin(), names.end(), "noop"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "random"), names.end());
  auto noop = make_policy("noop?space=joint_pos");
  EXPECT_EQ(noop->spec().action_space, ActionSpace::kJointPos);
  auto random = make_policy("random?seed=4&chunk=3");
  EXPECT_EQ(random->spec().replan_every, 3);
}

TEST(Registry, BadReferencesAreInputErrors) {
  try {
    make_policy("oracle2");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("policy: expected one of "), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("noop"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("got 'oracle2'"), std::string::npos);
  }
  try {
    make_policy("noop?speed=2");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "policy noop: expected one of the options space, cameras, got 'speed'");
  }
  try {
    make_policy("random?bogus=1");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "policy random: expected one of the options space, seed, scale, chunk, cameras, got 'bogus'");
  }
  try {
    make_policy("oracle?bogus=1");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "policy oracle: expected no options, got 'bogus'");
  }
  try {
    make_policy("random?seed=x");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "policy random: seed: expected an integer in [0, 18446744073709551615], got 'x'");
  }
}

TEST(Registry, NoopAndRandomTakeCameras) {
  EXPECT_EQ(make_policy("noop?cameras=agentview:224x224+wrist:224x224")->spec().cameras.size(), 2u);
  EXPECT_EQ(make_policy("random?seed=2&cameras=wrist:64x64")->spec().cameras.size(), 1u);
  EXPECT_TRUE(make_policy("noop")->spec().cameras.empty());
  try {
    make_policy("random?cameras=wrist");
    ADD_FAILURE();
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("policy random: cameras: expected NAME:WIDTHxHEIGHT"), std::string::npos)
        << e.what();
  }
}

TEST(Registry, IntegerOptionsAreExactIntegersInRange) {
  auto big = make_policy("random?seed=18446744073709551615&chunk=100000");
  EXPECT_EQ(big->spec().replan_every, 100000);
  for (const char* seed : {"nan", "inf", "-1", "0x10", "1e3", "1.5", "+3", " 3", "3 ", "",
                           "18446744073709551616", "1e30"}) {
    try {
      make_policy(std::string("random?seed=") + seed);
      FAIL() << seed;
    } catch (const core::InputError& e) {
      EXPECT_EQ(std::string(e.what()), std::string("policy random: seed: expected an integer in "
                                                   "[0, 18446744073709551615], got '") + seed + "'");
    }
  }
  for (const char* chunk : {"0", "100001", "2147483648", "nan", "2.0"}) {
    try {
      make_policy(std::string("random?chunk=") + chunk);
      FAIL() << chunk;
    } catch (const core::InputError& e) {
      EXPECT_EQ(std::string(e.what()),
                std::string("policy random: chunk: expected an integer in [1, 100000], got '") + chunk + "'");
    }
  }
  try {
    make_policy("random?scale=nan");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "policy random: scale: expected a finite number, got 'nan'");
  }
}

TEST(Registry, LaterLayersRegisterTheirOwn) {
  register_policy(PolicyEntry{"test_hold", "test", [](PolicyRef ref) {
                                reject_unknown_options(ref);
                                return std::unique_ptr<Policy>(new NoopPolicy());
                              }});
  EXPECT_NE(make_policy("test_hold"), nullptr);
}

}  // namespace
}  // namespace hribench::policy
