#pragma once
// Reading and writing scenario scripts and episode specs, all driven by the structs' single
// visit functions (script/scenario.h): YAML in (every problem collected, with
// "file:line:col (key.path)"), JSON out and in (exact doubles), and the key reference of the
// docs.

#include <string>
#include <string_view>
#include <vector>

#include "core/errors.h"
#include "core/json.h"
#include "script/scenario.h"

namespace hribench::script {

// Parses a script's text (named `file` in messages). Appends every YAML and schema problem
// (unknown keys, missing keys, wrong types, malformed values and distributions); returns what
// could be read. Cross-references are checked by script::check (script/check.h).
Scenario parse_scenario(std::string_view text, const std::string& file,
                        std::vector<core::InputError>& problems);
// Reads a script file (problems as above; "cannot open file" is one).
Scenario read_scenario(const std::string& path, std::vector<core::InputError>& problems);

// JSON forms. Unresolved values are written in their source form ("U(0.5, 3)").
core::Json to_json(const EpisodeSpec& spec);
core::Json to_json(const Scenario& scenario);
// Reads an EpisodeSpec written by to_json. Throws InputError (where = "SOURCE (key.path)").
EpisodeSpec episode_from_json(const core::Json& json, std::string_view source);

// The key reference of every struct of the grammar, as Markdown tables (for the docs; a test
// checks docs/scenario-scripts.md contains it).
std::string schema_reference_markdown();

}  // namespace hribench::script
