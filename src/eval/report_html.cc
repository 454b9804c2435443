#include "eval/report_html.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <utility>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"
#include "eval/aggregate.h"
#include "eval/episode_files.h"
#include "eval/metrics.h"

namespace hribench::eval {
namespace {

namespace fs = std::filesystem;

// Tableau 10: one colour per policy (in order of appearance), one per failure label.
constexpr const char* kPalette[] = {"#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#76b7b2",
                                    "#edc948", "#b07aa1", "#ff9da7", "#9c755f", "#bab0ac"};
constexpr size_t kPaletteSize = std::size(kPalette);
constexpr const char* kSuccessColour = "#59a14f";
constexpr const char* kHumanColour = "#d4604a";
constexpr const char* kRobotColour = "#4e79a7";

std::string escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

// A coordinate of an SVG drawing (0.1 px is finer than any screen).
std::string px(double v) { return fmt::format("{:.1f}", v); }

// Linear map of [d0, d1] onto [r0, r1].
struct Scale {
  double d0, d1, r0, r1;
  double operator()(double v) const { return d1 == d0 ? r0 : r0 + (v - d0) / (d1 - d0) * (r1 - r0); }
};

std::string estimate_cell(const std::optional<Estimate>& e) {
  if (!e) return "—";
  return fmt::format("{:.2f} <small>[{:.2f}, {:.2f}]</small>", e->value, e->low, e->high);
}

std::vector<std::string> policies_of(const RunResults& run) {
  std::vector<std::string> policies;
  for (const EpisodeResult& e : run.episodes) {
    if (std::find(policies.begin(), policies.end(), e.policy) == policies.end()) policies.push_back(e.policy);
  }
  return policies;
}

std::string policy_colour(const std::vector<std::string>& policies, const std::string& policy) {
  const auto it = std::find(policies.begin(), policies.end(), policy);
  return kPalette[static_cast<size_t>(it - policies.begin()) % kPaletteSize];
}

std::string label_colour(const std::string& label) {
  for (int i = 0; i < kNumFailureLabels; ++i) {
    if (to_string(static_cast<FailureLabel>(i)) == label) return kPalette[static_cast<size_t>(i) % kPaletteSize];
  }
  return "#888";
}

std::string legend(const std::vector<std::pair<std::string, std::string>>& entries) {
  std::string html = "<p class=\"legend\">";
  for (const auto& [name, colour] : entries) {
    html += fmt::format("<span><i style=\"background:{}\"></i>{}</span> ", colour, escape(name));
  }
  return html + "</p>\n";
}

std::string policy_legend(const std::vector<std::string>& policies) {
  std::vector<std::pair<std::string, std::string>> entries;
  for (const std::string& p : policies) entries.emplace_back(p, policy_colour(policies, p));
  return legend(entries);
}

// The headline table (summary.md's): role groups, then overall.
std::string headline_table(const RunResults& run) {
  std::vector<GroupSummary> rows = summarize(run.episodes, GroupBy::kRole, run.info.constants);
  for (GroupSummary& s : summarize(run.episodes, GroupBy::kOverall, run.info.constants)) rows.push_back(std::move(s));
  std::string html =
      "<table id=\"headline\"><tr><th>Role group</th><th>Policy</th><th>Episodes</th><th>CSR↑</th><th>CT↓ "
      "(s)</th><th>Rsp↓ (s)</th><th>TSync↑</th><th>OC↑</th><th>Safety↑</th></tr>\n";
  for (const GroupSummary& s : rows) {
    html += fmt::format(
        "<tr{}><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
        s.group == "overall" ? " class=\"overall\"" : "", escape(group_label(s)), escape(s.policy), s.episodes,
        estimate_cell(s.csr), estimate_cell(s.ct), estimate_cell(s.rsp), estimate_cell(s.tsync),
        estimate_cell(s.oc), s.safety ? fmt::format("{:.2f}", *s.safety) : "—");
  }
  return html + "</table>\n";
}

// CSR of every (group, policy) as bars with their Wilson intervals as whiskers.
std::string csr_chart(const std::string& id, const std::vector<GroupSummary>& rows,
                      const std::vector<std::string>& policies) {
  std::vector<std::string> groups;  // labels, in order of first appearance
  for (const GroupSummary& s : rows) {
    if (std::find(groups.begin(), groups.end(), group_label(s)) == groups.end()) groups.push_back(group_label(s));
  }
  const double bar = 16;
  const double gap = 22;
  const double left = 44;
  const double top = 14;
  const double plot_height = 180;
  const double group_width = bar * static_cast<double>(policies.size()) + gap;
  const double width = std::max(420.0, left + group_width * static_cast<double>(groups.size()) + 10);
  const double height = top + plot_height + 90;
  const Scale y{0, 1, top + plot_height, top};
  std::string svg = fmt::format(
      "<svg id=\"{}\" class=\"chart\" xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" "
      "viewBox=\"0 0 {} {}\">\n",
      id, px(width), px(height), px(width), px(height));
  for (const double v : {0.0, 0.25, 0.5, 0.75, 1.0}) {
    svg += fmt::format("<line class=\"grid\" x1=\"{}\" x2=\"{}\" y1=\"{}\" y2=\"{}\"/><text x=\"{}\" y=\"{}\" "
                       "text-anchor=\"end\">{:.2f}</text>\n",
                       px(left), px(width - 6), px(y(v)), px(y(v)), px(left - 4), px(y(v) + 4), v);
  }
  svg += fmt::format("<text x=\"12\" y=\"{}\" transform=\"rotate(-90 12 {})\" text-anchor=\"middle\">CSR</text>\n",
                     px(y(0.5)), px(y(0.5)));
  for (size_t g = 0; g < groups.size(); ++g) {
    const double x0 = left + gap / 2 + group_width * static_cast<double>(g);
    for (size_t p = 0; p < policies.size(); ++p) {
      const auto it = std::find_if(rows.begin(), rows.end(), [&](const GroupSummary& s) {
        return group_label(s) == groups[g] && s.policy == policies[p];
      });
      if (it == rows.end() || !it->csr) continue;
      const Estimate& e = *it->csr;
      const double x = x0 + bar * static_cast<double>(p);
      svg += fmt::format(
          "<rect class=\"bar\" data-policy=\"{}\" data-group=\"{}\" data-value=\"{}\" x=\"{}\" y=\"{}\" width=\"{}\" "
          "height=\"{}\" fill=\"{}\"><title>{} {}: CSR {:.2f} [{:.2f}, {:.2f}], {} episodes</title></rect>\n",
          escape(policies[p]), escape(groups[g]), e.value, px(x + 1), px(y(e.value)), px(bar - 2),
          px(y(0) - y(e.value)), policy_colour(policies, policies[p]), escape(groups[g]), escape(policies[p]), e.value,
          e.low, e.high, e.n);
      const double cx = x + bar / 2;
      svg += fmt::format(
          "<path class=\"interval\" d=\"M{} {}V{}M{} {}H{}M{} {}H{}\"/>\n", px(cx), px(y(e.low)), px(y(e.high)),
          px(cx - 3), px(y(e.low)), px(cx + 3), px(cx - 3), px(y(e.high)), px(cx + 3));
    }
    const double label_x = x0 + bar * static_cast<double>(policies.size()) / 2;
    svg += fmt::format("<text x=\"{}\" y=\"{}\" transform=\"rotate(-35 {} {})\" text-anchor=\"end\">{}</text>\n",
                       px(label_x), px(top + plot_height + 14), px(label_x), px(top + plot_height + 14),
                       escape(groups[g]));
  }
  return svg + "</svg>\n";
}

// Per policy, one horizontal bar of its episodes split by primary failure label (and successes).
std::string failure_chart(const RunResults& run, const std::vector<std::string>& policies) {
  const std::vector<GroupSummary> overall = summarize(run.episodes, GroupBy::kOverall, run.info.constants);
  const double left = 110;
  const double bar_width = 560;
  const double row = 26;
  const double height = 20 + row * static_cast<double>(policies.size());
  std::string svg = fmt::format(
      "<svg id=\"failures\" class=\"chart\" xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\">\n",
      px(left + bar_width + 20), px(height));
  std::set<std::string> shown;
  std::map<std::string, int> successes;
  for (const EpisodeResult& e : run.episodes) successes[e.policy] += e.metrics.success ? 1 : 0;
  for (size_t p = 0; p < policies.size(); ++p) {
    const auto it = std::find_if(overall.begin(), overall.end(), [&](const GroupSummary& s) { return s.policy == policies[p]; });
    if (it == overall.end() || it->episodes == 0) continue;
    const double y = 10 + row * static_cast<double>(p);
    const Scale x{0, static_cast<double>(it->episodes), left, left + bar_width};
    svg += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{}</text>\n", px(left - 6), px(y + 14),
                       escape(policies[p]));
    double at = 0;
    const auto segment = [&](const std::string& cls, const std::string& name, int count, const std::string& colour) {
      svg += fmt::format(
          "<rect class=\"{}\" data-policy=\"{}\" data-label=\"{}\" data-value=\"{}\" x=\"{}\" y=\"{}\" width=\"{}\" "
          "height=\"{}\" fill=\"{}\"><title>{}: {} {} of {}</title></rect>\n",
          cls, escape(policies[p]), escape(name), count, px(x(at)), px(y), px(x(at + count) - x(at)), px(row - 6),
          colour, escape(policies[p]), escape(name), count, it->episodes);
      at += count;
    };
    if (successes[policies[p]] > 0) segment("success", "success", successes[policies[p]], kSuccessColour);
    // Labels in priority order (docs/metrics.md "Failure modes").
    for (int l = 0; l < kNumFailureLabels; ++l) {
      const std::string label(to_string(static_cast<FailureLabel>(l)));
      const auto count = it->failures.find(label);
      if (count == it->failures.end() || count->second == 0) continue;
      segment("bar", label, count->second, label_colour(label));
      shown.insert(label);
    }
  }
  svg += "</svg>\n";
  std::vector<std::pair<std::string, std::string>> entries{{"success", kSuccessColour}};
  for (int l = 0; l < kNumFailureLabels; ++l) {
    const std::string label(to_string(static_cast<FailureLabel>(l)));
    if (shown.count(label)) entries.emplace_back(label, label_colour(label));
  }
  return legend(entries) + svg;
}

// One row per policy, one dot per episode that has the metric, and the median as a tick.
std::string distribution_chart(const std::string& id, const std::string& unit, const RunResults& run,
                               const std::vector<std::string>& policies,
                               std::optional<double> (*value)(const EpisodeMetrics&), double fixed_max) {
  double max = fixed_max;
  for (const EpisodeResult& e : run.episodes) {
    if (const auto v = value(e.metrics)) max = std::max(max, *v);
  }
  const double left = 110;
  const double plot_width = 560;
  const double row = 30;
  const double height = 34 + row * static_cast<double>(policies.size());
  const Scale x{0, max, left, left + plot_width};
  std::string svg = fmt::format(
      "<svg id=\"{}\" class=\"chart\" xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\">\n", id,
      px(left + plot_width + 30), px(height));
  const double axis_y = 8 + row * static_cast<double>(policies.size());
  for (int i = 0; i <= 4; ++i) {
    const double v = max * i / 4;
    svg += fmt::format("<line class=\"grid\" x1=\"{}\" x2=\"{}\" y1=\"6\" y2=\"{}\"/><text x=\"{}\" y=\"{}\" "
                       "text-anchor=\"middle\">{:.2f}{}</text>\n",
                       px(x(v)), px(x(v)), px(axis_y), px(x(v)), px(axis_y + 14), v, unit);
  }
  for (size_t p = 0; p < policies.size(); ++p) {
    const double y = 8 + row * (static_cast<double>(p) + 0.5);
    svg += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{}</text>\n", px(left - 6), px(y + 4),
                       escape(policies[p]));
    std::vector<double> values;
    for (size_t i = 0; i < run.episodes.size(); ++i) {
      const EpisodeResult& e = run.episodes[i];
      const auto v = e.policy == policies[p] ? value(e.metrics) : std::nullopt;
      if (!v) continue;
      values.push_back(*v);
      // A deterministic jitter keeps equal values apart.
      const double jitter = static_cast<double>(static_cast<int>(values.size() % 5) - 2) * 3.5;
      svg += fmt::format(
          "<circle class=\"dot\" data-policy=\"{}\" cx=\"{}\" cy=\"{}\" r=\"3.5\" fill=\"{}\"><title>{} {} seed {}: "
          "{:.3f}{}</title></circle>\n",
          escape(e.policy), px(x(*v)), px(y + jitter), policy_colour(policies, e.policy), escape(e.task), escape(e.policy),
          e.seed, *v, unit);
    }
    if (!values.empty()) {
      const double m = median(values);
      svg += fmt::format("<path class=\"median\" d=\"M{} {}V{}\"><title>median {:.3f}{}</title></path>\n", px(x(m)),
                         px(y - 11), px(y + 11), m, unit);
    }
  }
  return svg + "</svg>\n";
}

std::string labels_text(const EpisodeMetrics& m) {
  std::string text;
  for (const FailureLabel l : m.labels) text += (text.empty() ? "" : ", ") + std::string(to_string(l));
  return text.empty() ? "—" : text;
}

std::string episode_table(const RunResults& run, const std::vector<EpisodeFiles>& files) {
  std::string html =
      "<table id=\"episodes\"><tr><th>Task</th><th>Variant</th><th>Policy</th><th>Seed</th><th>Status</th>"
      "<th>Success</th><th>CT (s)</th><th>Rsp (s)</th><th>Labels</th><th>Video</th><th>Replay</th></tr>\n";
  for (size_t i = 0; i < run.episodes.size(); ++i) {
    const EpisodeResult& e = run.episodes[i];
    const std::string stem = episode_stem(e);
    const auto link = [&](bool exists, const std::string& href, const char* text) {
      return exists ? fmt::format("<a href=\"{}\">{}</a>", escape(href), text) : std::string("—");
    };
    html += fmt::format(
        "<tr class=\"episode {}\" data-stem=\"{}\"><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
        "<td>{:.2f}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
        e.metrics.success ? "success" : "failure", escape(stem),
        escape(e.task_id.empty() ? e.task : e.task_id + " " + e.task), escape(e.variant.empty() ? "—" : e.variant),
        escape(e.policy), e.seed,
        escape(e.status == core::EpisodeStatus::kOk ? "ok" : std::string(core::to_string(e.status)) + ": " +
                                                                  e.status_reason),
        e.metrics.success ? "yes" : "no", e.metrics.completion_time,
        e.metrics.response_latency ? fmt::format("{:.2f}", *e.metrics.response_latency) : "—",
        escape(labels_text(e.metrics)), link(files[i].video, "videos/" + stem + ".mp4", "video"),
        link(files[i].replay, "replay/" + stem + ".html", "3D replay"));
  }
  return html + "</table>\n";
}

// ---------------------------------------------------------------------------------------------
// The timeline of one episode.

struct Span {
  std::string name;
  double from = 0;
  double to = 0;
};

// Acts of one actor as spans from ".start" to ".end" (still running at the end: to the end).
std::vector<Span> act_spans(const EpisodeLog& log, Actor actor, double end) {
  std::vector<Span> spans;
  for (const Event& e : log.events) {
    if (e.actor != actor) continue;
    const auto strip = [&](std::string_view suffix) {
      return e.name.size() > suffix.size() && e.name.ends_with(suffix)
                 ? std::optional<std::string>(e.name.substr(0, e.name.size() - suffix.size()))
                 : std::nullopt;
    };
    if (e.kind == EventKind::kActStart) {
      spans.push_back({strip(".start").value_or(e.name), e.time, end});
    } else if (e.kind == EventKind::kActEnd) {
      const std::string name = strip(".end").value_or(e.name);
      for (auto it = spans.rbegin(); it != spans.rend(); ++it) {
        if (it->name == name && it->to == end) {
          it->to = e.time;
          break;
        }
      }
    }
  }
  return spans;
}

std::string polyline(const std::vector<std::pair<double, double>>& points, const std::string& cls,
                     const std::string& colour) {
  std::string d;
  for (const auto& [x, y] : points) d += (d.empty() ? "M" : "L") + px(x) + " " + px(y);
  return d.empty() ? "" : fmt::format("<path class=\"{}\" d=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\"/>\n",
                                      cls, d, colour);
}

std::string timeline_chart(const ReportTimeline& t, const MetricConstants& c) {
  const EpisodeLog& log = t.log;
  const double end = log.steps.empty() ? 0 : log.steps.back().time;
  const double start = log.steps.empty() ? 0 : log.steps.front().time;
  const double left = 120;
  const double plot_width = 760;
  const double lane = 26;
  const Scale x{start, std::max(end, start + 1e-9), left, left + plot_width};
  const std::vector<Span> human = act_spans(log, Actor::kHuman, end);
  const std::vector<Span> robot = act_spans(log, Actor::kRobot, end);
  const double human_top = 22;
  const double cue_top = human_top + lane * static_cast<double>(std::max<size_t>(human.size(), 1));
  const double robot_top = cue_top + lane;
  const double contact_top = robot_top + lane * static_cast<double>(std::max<size_t>(robot.size(), 1));
  const double separation_top = contact_top + lane + 10;
  const double separation_height = 150;
  const double force_top = separation_top + separation_height + 24;
  const double force_height = 90;
  const double height = force_top + force_height + 30;
  std::string svg = fmt::format(
      "<svg id=\"timeline\" class=\"chart\" xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\">\n",
      px(left + plot_width + 70), px(height));
  // Time grid, one line a second (every 5 s past 20 s).
  const double tick = end - start > 20 ? 5 : 1;
  for (double s = std::ceil(start); s <= end + 1e-9; s += tick) {
    svg += fmt::format("<line class=\"grid\" x1=\"{}\" x2=\"{}\" y1=\"16\" y2=\"{}\"/><text x=\"{}\" y=\"{}\" "
                       "text-anchor=\"middle\">{:g}</text>\n",
                       px(x(s)), px(x(s)), px(height - 24), px(x(s)), px(height - 10), s);
  }
  svg += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"end\">t (s)</text>\n", px(left - 6), px(height - 10));
  const auto lane_label = [&](double y, const std::string& text) {
    svg += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{}</text>\n", px(left - 6), px(y + 15),
                       escape(text));
  };
  const auto spans = [&](const std::vector<Span>& list, double top, const char* cls, const char* colour) {
    for (size_t i = 0; i < list.size(); ++i) {
      const Span& s = list[i];
      const double y = top + lane * static_cast<double>(i);
      svg += fmt::format(
          "<rect class=\"{}\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"{}\"><title>{}: {:.2f} – {:.2f} "
          "s</title></rect><text x=\"{}\" y=\"{}\" class=\"in-bar\">{}</text>\n",
          cls, px(x(s.from)), px(y + 3), px(std::max(2.0, x(s.to) - x(s.from))), px(lane - 6), colour,
          escape(s.name), s.from, s.to, px(x(s.from) + 3), px(y + 17), escape(s.name));
    }
  };
  lane_label(human_top, "human acts");
  spans(human, human_top, "act human", kHumanColour);
  lane_label(cue_top, "cues");
  lane_label(robot_top, "robot acts");
  spans(robot, robot_top, "act robot", kRobotColour);
  lane_label(contact_top, "contacts");
  for (const Event& e : log.events) {
    if (e.kind == EventKind::kCue) {
      const double cx = x(e.time);
      svg += fmt::format(
          "<path class=\"cue\" d=\"M{} {}l6 9l-6 9l-6 -9z\" fill=\"{}\"><title>cue {} at {:.2f} s</title></path>"
          "<text x=\"{}\" y=\"{}\">{}</text>\n",
          px(cx), px(cue_top + 2), kHumanColour, escape(e.name), e.time, px(cx + 8), px(cue_top + 16), escape(e.name));
    } else if (e.kind == EventKind::kActEnd && e.actor == Actor::kRobot) {
      // A robot act's goal first held (the log has no start for it: onsets are detected by the
      // metrics, docs/metrics.md).
      const double cx = x(e.time);
      svg += fmt::format(
          "<path class=\"goal robot\" d=\"M{} {}l6 9l-6 9l-6 -9z\" fill=\"{}\"><title>robot act {} at {:.2f} "
          "s</title></path><text class=\"small\" x=\"{}\" y=\"{}\">{}</text>\n",
          px(cx), px(robot_top + 2), kRobotColour, escape(e.name), e.time, px(cx + 7), px(robot_top + 15),
          escape(e.name.ends_with(".end") ? e.name.substr(0, e.name.size() - 4) : e.name));
    } else if (e.kind == EventKind::kContactBegin || e.kind == EventKind::kWarning) {
      const bool contact = e.kind == EventKind::kContactBegin;
      svg += fmt::format(
          "<path class=\"{}\" d=\"M{} {}v18\" stroke=\"{}\" stroke-width=\"2\"><title>{} {} at {:.2f} s "
          "{}</title></path>\n",
          contact ? "contact" : "warning", px(x(e.time)), px(contact_top + 3), contact ? "#333" : "#e15759",
          contact ? "contact" : "warning", escape(e.name), e.time, escape(e.detail));
    }
  }
  // Separation d(t) against S_p(t), clipped to the monitored distance's neighbourhood.
  std::vector<std::pair<double, double>> d_points;
  std::vector<std::pair<double, double>> sp_points;
  const double d_max = std::max(0.5, 1.5 * c.monitored_distance);
  const Scale yd{0, d_max, separation_top + separation_height, separation_top};
  std::string violations;
  for (size_t k = 0; k < log.steps.size(); ++k) {
    const StepRecord& s = log.steps[k];
    if (!std::isfinite(s.separation)) continue;
    const double sp = protective_separation(s.approach_speed, s.separation, c);
    d_points.emplace_back(x(s.time), yd(std::clamp(s.separation, 0.0, d_max)));
    sp_points.emplace_back(x(s.time), yd(std::clamp(sp, 0.0, d_max)));
    if (k > 0 && s.separation < sp && s.separation <= c.monitored_distance) {
      const double from = x(log.steps[k - 1].time);
      violations += fmt::format("<rect class=\"violation\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/>", px(from),
                                px(separation_top), px(x(s.time) - from), px(separation_height));
    }
  }
  lane_label(separation_top, "separation (m)");
  svg += fmt::format("<rect class=\"frame\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/>\n", px(left),
                     px(separation_top), px(plot_width), px(separation_height));
  svg += violations + "\n";
  for (const double v : {0.0, d_max / 2, d_max}) {
    svg += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{:.2f}</text>\n", px(left - 6), px(yd(v) + 4), v);
  }
  if (d_points.empty()) {
    svg += fmt::format("<text x=\"{}\" y=\"{}\">no human in this episode</text>\n", px(left + 10),
                       px(separation_top + 20));
  }
  svg += polyline(d_points, "separation", "#4e79a7");
  svg += polyline(sp_points, "protective", "#e15759");
  // Contact forces: the sum of normal forces on the human, and on everything else.
  double f_max = 10;
  for (const StepRecord& s : log.steps) {
    for (const Contact& ct : s.contacts) f_max = std::max(f_max, ct.normal_force);
  }
  const Scale yf{0, f_max, force_top + force_height, force_top};
  std::vector<std::pair<double, double>> human_force;
  std::vector<std::pair<double, double>> other_force;
  for (const StepRecord& s : log.steps) {
    double on_human = 0;
    double on_other = 0;
    for (const Contact& ct : s.contacts) (ct.other_kind == ContactOther::kHuman ? on_human : on_other) += ct.normal_force;
    human_force.emplace_back(x(s.time), yf(std::min(on_human, f_max)));
    other_force.emplace_back(x(s.time), yf(std::min(on_other, f_max)));
  }
  lane_label(force_top, "contact force (N)");
  svg += fmt::format("<rect class=\"frame\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/>\n", px(left),
                     px(force_top), px(plot_width), px(force_height));
  for (const double v : {0.0, f_max}) {
    svg += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{:.0f}</text>\n", px(left - 6), px(yf(v) + 4), v);
  }
  svg += polyline(other_force, "force-other", "#9c755f");
  svg += polyline(human_force, "force-human", kHumanColour);
  return svg + "</svg>\n";
}

std::string timeline_section(const ReportTimeline* t, const MetricConstants& c) {
  std::string html = "<h2 id=\"timeline-section\">Timeline of one episode</h2>\n";
  if (!t) {
    return html +
           "<p class=\"no-timeline\">No timeline: no episode of this run has a saved log (run eval with "
           "--save-logs to keep them).</p>\n";
  }
  const EpisodeLog& log = t->log;
  html += fmt::format(
      "<p><b>{}</b> ({}): {} seed {}, policy {}, {:.2f} s, status {}{}. Lanes: the human's acts and cues, the "
      "robot's acts (diamonds: the moment an act's goal first held), contacts (ticks) and warnings (red ticks); separation d(t) (blue) against the protective "
      "distance S<sub>p</sub>(t) (red), shaded where d &lt; S<sub>p</sub> within {:.1f} m (docs/metrics.md, "
      "HCS); contact forces on the human (red) and on everything else (brown).</p>\n",
      escape(t->stem), escape(t->chosen_because), escape(log.task), log.seed, escape(log.policy), log.duration(),
      escape(std::string(core::to_string(log.status))), log.status_reason.empty() ? "" : ": " + escape(log.status_reason),
      c.monitored_distance);
  return html + timeline_chart(*t, c);
}

constexpr const char* kStyle = R"(
body{font:14px/1.45 system-ui,sans-serif;margin:24px auto;max-width:1100px;color:#222;padding:0 16px}
h1{font-size:22px}h2{font-size:18px;margin-top:28px;border-bottom:1px solid #ddd}
table{border-collapse:collapse;margin:8px 0}td,th{border:1px solid #ddd;padding:3px 7px;text-align:left}
th{background:#f3f3f3}tr.overall td{font-weight:600}tr.failure td:nth-child(6){color:#b2332a}
small{color:#777}.legend span{margin-right:14px;white-space:nowrap}
.legend i{display:inline-block;width:11px;height:11px;margin-right:4px;vertical-align:-1px}
svg.chart{display:block;margin:6px 0 12px;font-size:11px;overflow:visible}svg text{fill:#333}
.grid{stroke:#e6e6e6}.interval{stroke:#222;stroke-width:1.2;fill:none}.median{stroke:#222;stroke-width:2}
.frame{fill:none;stroke:#ccc}.violation{fill:#e15759;opacity:.15}.in-bar{fill:#fff;font-size:10px}
.provenance{color:#666;font-size:12px}text.small{font-size:10px}
)";

}  // namespace

std::string report_html(const RunResults& run, const std::vector<EpisodeFiles>& files, const ReportTimeline* timeline) {
  HRIB_CHECK(files.size() == run.episodes.size());
  const std::vector<std::string> policies = policies_of(run);
  std::string html = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>HRIBench report</title>\n";
  html += "<style>" + std::string(kStyle) + "</style></head><body>\n<h1>HRIBench report</h1>\n";
  html += fmt::format(
      "<p class=\"provenance\">HRIBench {} (git {}), MuJoCo {}; {} episodes; options <code>{}</code>. Charts are "
      "drawn by HRIBench itself (docs/report.md); intervals are 95 % (Wilson for rates, bootstrap for means, "
      "docs/metrics.md).</p>\n",
      escape(run.info.hribench_version), escape(run.info.git_hash), escape(run.info.mujoco_version),
      run.episodes.size(), escape(run.info.options.dump()));
  html += "<h2>Headline</h2>\n" + headline_table(run);
  html += "<h2>CSR per task</h2>\n" + policy_legend(policies) +
          csr_chart("csr-by-task", summarize(run.episodes, GroupBy::kTask, run.info.constants), policies);
  html += "<h2>CSR per role group</h2>\n" +
          csr_chart("csr-by-role", summarize(run.episodes, GroupBy::kRole, run.info.constants), policies);
  html += "<h2>Failure labels</h2>\n<p>Each policy's episodes by primary failure label (docs/metrics.md).</p>\n" +
          failure_chart(run, policies);
  html += "<h2>Response latency (Rsp)</h2>\n<p>One dot per episode with a cue; the tick is the median.</p>\n" +
          distribution_chart("rsp", " s", run, policies,
                             [](const EpisodeMetrics& m) { return m.response_latency; }, 0.5);
  html += "<h2>Temporal synchrony (TSync)</h2>\n<p>One dot per episode with a synchrony; the tick is the median.</p>\n" +
          distribution_chart("tsync", "", run, policies, [](const EpisodeMetrics& m) { return m.tsync; }, 1.0);
  html += "<h2>Episodes</h2>\n" + episode_table(run, files);
  html += timeline_section(timeline, run.info.constants);
  return html + "</body></html>\n";
}

fs::path write_report_html(const fs::path& dir, const RunResults& run, std::string_view episode) {
  std::vector<EpisodeFiles> files;
  files.reserve(run.episodes.size());
  std::error_code ec;
  for (const EpisodeResult& e : run.episodes) {
    const std::string stem = episode_stem(e);
    files.push_back({fs::is_regular_file(log_file(dir, stem), ec), fs::is_regular_file(video_file(dir, stem), ec),
                     fs::is_regular_file(replay_file(dir, stem), ec)});
  }
  std::optional<ReportTimeline> timeline;
  if (!episode.empty()) {
    const fs::path path = find_episode_log(dir, episode, "--episode");
    timeline = ReportTimeline{path.stem().string(), "--episode", load_episode_log(path)};
  } else {
    const auto chosen = [&](bool failed) -> std::optional<size_t> {
      for (size_t i = 0; i < run.episodes.size(); ++i) {
        if (files[i].log && (!failed || !run.episodes[i].metrics.success)) return i;
      }
      return std::nullopt;
    };
    const std::optional<size_t> failed = chosen(true);
    const std::optional<size_t> any = failed ? failed : chosen(false);
    if (any) {
      const std::string stem = episode_stem(run.episodes[*any]);
      timeline = ReportTimeline{stem,
                                failed ? "the first failed episode with a saved log"
                                       : "no episode failed: the first episode with a saved log",
                                load_episode_log(log_file(dir, stem))};
    }
  }
  const fs::path path = dir / "report.html";
  core::write_file_atomically(path, report_html(run, files, timeline ? &*timeline : nullptr));
  return path;
}

}  // namespace hribench::eval
