#pragma once
// The scenario validator: every problem of a script, before any physics (docs/scenario-scripts.md
// "Validation"). A problem is where ("file:line:col (key.path)") plus what is wrong.

#include <string>
#include <string_view>
#include <vector>

#include "core/errors.h"
#include "script/scenario.h"

namespace hribench::script {

struct Problem {
  std::string where;    // "file:line:col (key.path)"
  std::string message;  // "expected X, got Y" or a sentence
  std::string text() const { return where + ": " + message; }
};

// Reads and validates a script file: YAML, schema and semantic problems, all of them, sorted
// by position. Empty = the script is clean.
std::vector<Problem> check(const std::string& path);
// The same for text already in memory (`file` names it in messages).
std::vector<Problem> check_text(std::string_view text, const std::string& file);
// Semantic problems of a parsed scenario (references, types, distributions, motion
// parameters, predicates, the constraint graph, windows).
std::vector<Problem> validate(const Scenario& scenario);

// Reads a script and throws the first problem (as core::InputError) unless it is clean.
Scenario load_scenario(const std::string& path);

// Object kinds, colours, robot parts and human body regions a script may name.
const std::vector<std::string>& object_kinds();
const std::vector<std::string>& object_colors();

}  // namespace hribench::script
