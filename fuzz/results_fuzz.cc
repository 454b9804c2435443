// Results files (results.json, then re-aggregated as `report` does) and journal lines
// (episodes.jsonl: one episode per line).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/errors.h"
#include "core/json.h"
#include "eval/aggregate.h"
#include "eval/report.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const hribench::eval::RunResults run =
        hribench::eval::results_from_json(hribench::core::parse_json(text, "fuzz.json"), "fuzz.json");
    hribench::eval::summary_markdown(run);
  } catch (const hribench::core::InputError&) {
  }
  size_t start = 0;
  for (size_t line = 1; start < text.size(); ++line) {
    const size_t end = text.find('\n', start);
    if (end == std::string_view::npos) break;
    try {
      hribench::eval::episode_from_json(
          hribench::core::parse_json(text.substr(start, end - start), "fuzz.jsonl", line), "fuzz.jsonl");
    } catch (const hribench::core::InputError&) {
    }
    start = end + 1;
  }
  return 0;
}
