#pragma once
// sample(scenario, seed) -> EpisodeSpec: every random choice of a script resolved with a
// seeded core::Rng. Streams are split per section and per name (variant, vars.NAME,
// scene.NAME, distractors, human, acts.NAME, safety), so adding a draw in one place does not
// shift the draws of another. Same scenario + seed => bit-identical spec and hash.

#include <cstdint>
#include <string>

#include "script/scenario.h"

namespace hribench::script {

// Requires a scenario that script::check found clean (otherwise throws InputError for what it
// cannot resolve). `robot` is recorded in the spec (and so in its hash); the draws do not
// depend on it.
EpisodeSpec sample(const Scenario& scenario, uint64_t seed, std::string_view robot = kDefaultRobot);

// SHA-256 (hex) of the spec's canonical JSON.
std::string spec_hash(const EpisodeSpec& spec);

// The spec as indented JSON text, and back (where = "SOURCE (key.path)").
std::string spec_to_text(const EpisodeSpec& spec);
EpisodeSpec spec_from_text(std::string_view text, std::string_view source);

// Table area where distractors are placed (x, y ranges in m), their minimum centre spacing,
// the gap kept between footprint circles (m), and the draws tried per distractor before it is
// left out.
inline constexpr double kDistractorXMin = 0.25, kDistractorXMax = 0.75;
inline constexpr double kDistractorYMin = -0.40, kDistractorYMax = 0.40;
inline constexpr double kDistractorSpacing = 0.12;
inline constexpr double kDistractorGap = 0.02;
inline constexpr int kDistractorAttempts = 50;

}  // namespace hribench::script
