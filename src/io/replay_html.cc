#include "io/replay_html.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/files.h"
#include "core/paths.h"
#include "eval/episode.h"
#include "eval/episode_files.h"
#include "eval/metrics.h"
#include "eval/report.h"
#include "eval/script_driver.h"
#include "gen/pool.h"
#include "human/hand.h"
#include "script/check.h"
#include "script/sample.h"
#include "script/scenario.h"
#include "sim/data.h"

namespace hribench::io {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw core::InputError(path.string(), "three.js (the npm package three pinned in package.json)",
                           "no such file: run scripts/install-deps.sh");
  }
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// three.js without its comment lines, comment blocks and blank lines and without the tabs that
// indent its lines (half its size). Only whole lines are left out: a block comment is one that
// starts a line, and code after its end on the same line is kept.
std::string strip_comment_lines(std::string_view js) {
  std::string out;
  out.reserve(js.size() / 2);
  bool in_block = false;
  size_t at = 0;
  while (at < js.size()) {
    size_t end = js.find('\n', at);
    if (end == std::string_view::npos) end = js.size();
    std::string_view line = js.substr(at, end - at);
    at = end + 1;
    const size_t first = line.find_first_not_of(" \t\r");
    std::string_view text = first == std::string_view::npos ? std::string_view() : line.substr(first);
    if (in_block) {
      const size_t close = text.find("*/");
      if (close == std::string_view::npos) continue;
      in_block = false;
      text = text.substr(close + 2);
    } else if (text.starts_with("/*")) {
      const size_t close = text.find("*/", 2);
      if (close == std::string_view::npos) {
        in_block = true;
        continue;
      }
      text = text.substr(close + 2);
    } else if (text.starts_with("//")) {
      continue;
    }
    if (text.find_first_not_of(" \t\r") == std::string_view::npos) continue;
    out.append(text);
    out += '\n';
  }
  return out;
}

std::string base64(const uint8_t* data, size_t size) {
  static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  for (size_t i = 0; i < size; i += 3) {
    const uint32_t n = (uint32_t{data[i]} << 16) | (i + 1 < size ? uint32_t{data[i + 1]} << 8 : 0) |
                       (i + 2 < size ? uint32_t{data[i + 2]} : 0);
    out += kDigits[(n >> 18) & 63];
    out += kDigits[(n >> 12) & 63];
    out += i + 1 < size ? kDigits[(n >> 6) & 63] : '=';
    out += i + 2 < size ? kDigits[n & 63] : '=';
  }
  return out;
}

// A value rounded for the page (shorter JSON; 0.1 mm and 0.1 ms are finer than the page shows).
double rounded(double v) { return std::round(v * 1e4) / 1e4; }

json vec(const mjtNum* v, int n) {
  json a = json::array();
  for (int i = 0; i < n; ++i) a.push_back(rounded(v[i]));
  return a;
}

const char* geom_type_name(int type) {
  switch (type) {
    case mjGEOM_PLANE: return "plane";
    case mjGEOM_SPHERE: return "sphere";
    case mjGEOM_CAPSULE: return "capsule";
    case mjGEOM_ELLIPSOID: return "ellipsoid";
    case mjGEOM_CYLINDER: return "cylinder";
    case mjGEOM_BOX: return "box";
    default: return nullptr;  // meshes, height fields: none in HRIBench's models
  }
}

const char* category(const model::GeomTag& tag) {
  if (tag.is_robot()) return "robot";
  if (tag.is_human()) return "human";
  if (tag.owner == model::GeomOwner::kObject) return "object";
  return "scene";
}

// The geoms MuJoCo's viewer shows (groups 0-2, not transparent), by body.
json body_geoms(const model::Model& model, int body, std::string& body_category) {
  const mjModel& m = *model.m();
  json geoms = json::array();
  for (int g = 0; g < m.ngeom; ++g) {
    const char* type = geom_type_name(m.geom_type[g]);
    if (m.geom_bodyid[g] != body || m.geom_group[g] > 2 || !type) continue;
    const float* rgba = m.geom_matid[g] >= 0 ? m.mat_rgba + 4 * m.geom_matid[g] : m.geom_rgba + 4 * g;
    if (rgba[3] <= 0) continue;
    json size = vec(m.geom_size + 3 * g, 3);
    if (m.geom_type[g] == mjGEOM_PLANE) {
      for (int i = 0; i < 2; ++i) size[i] = size[i].get<double>() > 0 ? size[i].get<double>() : 3.0;
    }
    geoms.push_back({{"type", type},
                     {"size", size},
                     {"pos", vec(m.geom_pos + 3 * g, 3)},
                     {"quat", vec(m.geom_quat + 4 * g, 4)},
                     {"rgba", {rgba[0], rgba[1], rgba[2], rgba[3]}}});
    if (body_category.empty()) body_category = category(model.geom_tags[static_cast<size_t>(g)]);
  }
  return geoms;
}

// The drawn hands' parts (human/hand.h) as bodies of the page, each with its capsules in the
// part's frame and in the colour of its hand's contact capsule (which the page, like the
// renderers, does not draw).
json hand_part_geoms(const model::Model& model, human::Side side, human::HandPart part) {
  const mjModel& m = *model.m();
  const float* rgba = nullptr;
  for (size_t c = 0; c < model.human_capsules.size(); ++c) {
    const human::BodyCapsule& capsule = model.human_capsules[c];
    if (capsule.region == human::BodyRegion::kHand && capsule.joint == human::wrist(side)) {
      rgba = m.geom_rgba + 4 * model.human_capsule_geom[c];
    }
  }
  HRIB_CHECK(rgba != nullptr) << "no hand capsule on the " << human::to_string(side) << " wrist";
  json geoms = json::array();
  for (const human::HandCapsule& c : human::hand_capsules(model.skeleton)) {
    if (c.part != part) continue;
    const core::Vec3 axis = c.to - c.from;
    const core::Quat q = core::Quat::FromTwoVectors(core::Vec3::UnitZ(), axis.normalized());
    const core::Vec3 mid = 0.5 * (c.from + c.to);
    geoms.push_back({{"type", "capsule"},
                     {"size", {c.radius, 0.5 * axis.norm(), 0.0}},
                     {"pos", {mid.x(), mid.y(), mid.z()}},
                     {"quat", {q.w(), q.x(), q.y(), q.z()}},
                     {"rgba", {rgba[0], rgba[1], rgba[2], rgba[3]}}});
  }
  return geoms;
}

// Contacts of the robot with anything else, as MuJoCo finds them in the re-posed step.
void contact_points(const model::Model& model, const sim::Data& data, int frame, json& points) {
  const mjData& d = *data.mj;
  for (int i = 0; i < d.ncon; ++i) {
    const mjContact& c = d.contact[i];
    const model::GeomTag& a = model.geom_tags[static_cast<size_t>(c.geom1)];
    const model::GeomTag& b = model.geom_tags[static_cast<size_t>(c.geom2)];
    if (a.is_robot() == b.is_robot()) continue;
    const model::GeomTag& other = a.is_robot() ? b : a;
    const char* kind = other.is_human() ? "human" : other.owner == model::GeomOwner::kObject ? "object" : "environment";
    points.push_back({frame, rounded(c.pos[0]), rounded(c.pos[1]), rounded(c.pos[2]), kind});
  }
}

int16_t quantized(double v, double scale) {
  return static_cast<int16_t>(std::clamp(std::lround(v * scale), -32767L, 32767L));
}

json episode_data(const model::Model& model, const eval::EpisodeLog& log, const eval::MetricConstants& c) {
  const mjModel& m = *model.m();
  const size_t frames = log.steps.size();
  // Every body's pose at every step: the model's bodies, then (with a person) the parts of the
  // drawn hands, left then right.
  const int hand_parts = model.has_human ? 2 * human::kNumHandParts : 0;
  const int slots = m.nbody + hand_parts;
  std::vector<double> poses(frames * static_cast<size_t>(slots) * 7);
  const auto pose = [&](size_t f, int b) { return &poses[(f * static_cast<size_t>(slots) + static_cast<size_t>(b)) * 7]; };
  sim::Data data = sim::make_data(model);
  json points = json::array();
  for (size_t f = 0; f < frames; ++f) {
    eval::pose_from_step(model, log, log.steps[f], data);
    for (int b = 0; b < m.nbody; ++b) {
      std::memcpy(pose(f, b), data.mj->xpos + 3 * b, 3 * sizeof(double));
      std::memcpy(pose(f, b) + 3, data.mj->xquat + 4 * b, 4 * sizeof(double));
    }
    if (model.has_human) {
      const auto X_W = human::hand_part_poses(model.skeleton, log.steps[f].human_pose, data.X_WJ);
      for (int k = 0; k < hand_parts; ++k) {
        const core::Pose& X = X_W[static_cast<size_t>(k / human::kNumHandParts)][static_cast<size_t>(k % human::kNumHandParts)];
        double* p = pose(f, m.nbody + k);
        p[0] = X.translation.x();
        p[1] = X.translation.y();
        p[2] = X.translation.z();
        core::quat_to_wxyz(X.rotation, p + 3);
      }
    }
    contact_points(model, data, static_cast<int>(f), points);
  }
  // Bodies that carry a visible geom; those whose pose never changes are posed once.
  json bodies = json::array();
  std::vector<int> body_index(static_cast<size_t>(slots), -1);
  std::vector<int> moving;
  for (int b = 0; b < slots; ++b) {
    std::string body_category = b < m.nbody ? "" : "human";
    std::string name;
    json geoms;
    if (b < m.nbody) {
      geoms = body_geoms(model, b, body_category);
      name = mj_id2name(&m, mjOBJ_BODY, b) ? mj_id2name(&m, mjOBJ_BODY, b) : "world";
    } else {
      const auto side = static_cast<human::Side>((b - m.nbody) / human::kNumHandParts);
      const auto part = static_cast<human::HandPart>((b - m.nbody) % human::kNumHandParts);
      geoms = hand_part_geoms(model, side, part);
      name = fmt::format("human_{}_{}", human::to_string(side), human::to_string(part));
    }
    const bool tcp_body = b == m.site_bodyid[model.tcp_site];
    if (geoms.empty() && !tcp_body) continue;
    bool still = true;
    for (size_t f = 1; f < frames && still; ++f) still = std::memcmp(pose(f, b), pose(0, b), 7 * sizeof(double)) == 0;
    json body{{"name", name},
              {"category", body_category.empty() ? "robot" : body_category},
              {"geoms", std::move(geoms)}};
    body["pose"] = still && frames > 0 ? vec(pose(0, b), 7) : json(nullptr);
    body_index[static_cast<size_t>(b)] = static_cast<int>(bodies.size());
    if (!still) moving.push_back(b);
    bodies.push_back(std::move(body));
  }
  std::vector<int16_t> quantized_poses;
  quantized_poses.reserve(frames * moving.size() * 7);
  for (size_t f = 0; f < frames; ++f) {
    for (const int b : moving) {
      const double* p = pose(f, b);
      for (int i = 0; i < 3; ++i) quantized_poses.push_back(quantized(p[i], 1000));
      for (int i = 3; i < 7; ++i) quantized_poses.push_back(quantized(p[i], 32767));
    }
  }
  json moving_index = json::array();
  for (const int b : moving) moving_index.push_back(body_index[static_cast<size_t>(b)]);
  // Per step: time, separation and S_p (null without a human), the log's contacts.
  json times = json::array();
  json separation = json::array();
  json protective = json::array();
  json contacts = json::array();
  for (size_t f = 0; f < frames; ++f) {
    const eval::StepRecord& s = log.steps[f];
    times.push_back(rounded(s.time));
    const bool human = std::isfinite(s.separation);
    separation.push_back(human ? json(rounded(s.separation)) : json(nullptr));
    protective.push_back(human ? json(rounded(eval::protective_separation(s.approach_speed, s.separation, c)))
                               : json(nullptr));
    for (const eval::Contact& ct : s.contacts) {
      contacts.push_back({f, ct.robot_part, ct.other, eval::to_string(ct.other_kind), rounded(ct.normal_force)});
    }
  }
  json events = json::array();
  for (const eval::Event& e : log.events) {
    if (e.kind == eval::EventKind::kPredicateChange || e.kind == eval::EventKind::kContactEnd) continue;
    events.push_back({{"t", rounded(e.time)}, {"kind", eval::to_string(e.kind)}, {"actor", eval::to_string(e.actor)},
                      {"name", e.name}, {"detail", e.detail}});
  }
  const int tcp_body = m.site_bodyid[model.tcp_site];
  return json{{"task", log.task},
              {"seed", log.seed},
              {"policy", log.policy},
              {"status", core::to_string(log.status)},
              {"status_reason", log.status_reason},
              {"monitored_distance", c.monitored_distance},
              {"times", std::move(times)},
              {"bodies", std::move(bodies)},
              {"moving", std::move(moving_index)},
              {"poses", base64(reinterpret_cast<const uint8_t*>(quantized_poses.data()),
                               quantized_poses.size() * sizeof(int16_t))},
              {"tcp",
               {{"body", body_index[static_cast<size_t>(tcp_body)]},
                {"pos", vec(m.site_pos + 3 * model.tcp_site, 3)},
                {"quat", vec(m.site_quat + 4 * model.tcp_site, 4)}}},
              {"separation", std::move(separation)},
              {"protective", std::move(protective)},
              {"contact_points", std::move(points)},
              {"contacts", std::move(contacts)},
              {"events", std::move(events)}};
}

// JSON inside a <script> element: '<' only occurs in its strings, where \u003c means the same.
std::string script_json(const json& data) {
  std::string text = data.dump();
  for (size_t at = text.find('<'); at != std::string::npos; at = text.find('<', at)) text.replace(at, 1, "\\u003c");
  return text;
}

// Text inside a <script type="text/plain"> element is raw: it must not hold what ends it or
// changes how the HTML parser reads it.
const std::string& raw_script_text(const std::string& text, const char* file) {
  std::string lower = text;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  if (lower.find("</script") != std::string::npos || lower.find("<!--") != std::string::npos) {
    throw core::InputError(file, "three.js 0.187 (package.json), which holds no \"</script\" nor \"<!--\"",
                           "a file that does: reinstall it with scripts/install-deps.sh");
  }
  return text;
}

constexpr const char* kPage = R"HTML(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><link rel="icon" href="data:,">
<title>HRIBench replay: {title}</title>
<style>
body{{margin:0;font:13px/1.4 system-ui,sans-serif;color:#222;background:#f4f5f7}}
header{{padding:8px 14px}}h1{{font-size:16px;margin:0}}
#view{{position:relative;height:62vh;min-height:320px;background:#dfe5ec;cursor:grab}}
#view canvas{{display:block}}
#hud{{position:absolute;left:10px;bottom:10px;background:rgba(255,255,255,.88);padding:6px 9px;border-radius:4px;max-width:46%}}
#separation{{display:inline-block;padding:1px 6px;border-radius:3px;color:#fff;background:#888}}
#controls{{display:flex;gap:8px;align-items:center;padding:8px 14px}}
#controls input[type=range]{{flex:1}}
#track{{position:relative;height:34px;margin:0 14px}}
#strip{{position:absolute;left:0;top:20px;width:100%;height:10px}}
.marker{{position:absolute;top:0;width:3px;height:18px;cursor:pointer}}
.marker.cue{{background:#d4604a}}.marker.act_start,.marker.act_end{{background:#4e79a7}}
.marker.human{{background:#d4604a}}.marker.contact_begin{{background:#333}}.marker.warning{{background:#e15759}}
.legend span{{margin-right:12px}}.legend i{{display:inline-block;width:10px;height:10px;margin-right:3px}}
footer{{padding:4px 14px 12px;color:#555}}
</style></head><body>
<header><h1>{title}</h1></header>
<div id="view"><div id="hud"><div id="clock"></div><div><span id="separation"></span></div><div id="acts"></div><div id="contacts"></div></div></div>
<div id="controls"><button id="play">▶ play</button><label>speed <select id="speed"><option>0.25</option><option>0.5</option><option selected>1</option><option>2</option><option>4</option></select></label><input id="scrub" type="range" min="0" value="0" step="1"></div>
<div id="track"><canvas id="strip"></canvas></div>
<footer><p class="legend">Separation: <span><i style="background:#59a14f"></i>farther than the monitored distance</span><span><i style="background:#edc948"></i>monitored, d ≥ S<sub>p</sub></span><span><i style="background:#e15759"></i>d &lt; S<sub>p</sub></span><span><i style="background:#aaa"></i>no human</span>. Markers: cues (red), acts (blue), contacts (black). Contact points: red on the person, orange on the environment, yellow on objects. Drag to turn, wheel to zoom, shift-drag to pan.</p><p>Made by <code>hribench replay-html</code> from the episode's log (docs/report.md).</p></footer>
<script type="application/json" id="replay-data">{data}</script>
<script type="text/plain" id="three-core">{three_core}</script>
<script type="text/plain" id="three-module">{three_module}</script>
<script type="module">{app}</script>
</body></html>
)HTML";

// The page's program: three.js from blob: URLs, the scene, the timeline and the test hooks.
constexpr const char* kApp = R"JS(
const D = JSON.parse(document.getElementById('replay-data').textContent);
const source = (id) => document.getElementById(id).textContent;
const moduleUrl = (text) => URL.createObjectURL(new Blob([text], {type: 'text/javascript'}));
const coreUrl = moduleUrl(source('three-core'));
const THREE = await import(moduleUrl(source('three-module').replaceAll("'./three.core.js'", JSON.stringify(coreUrl))));

const bytes = Uint8Array.from(atob(D.poses), (c) => c.charCodeAt(0));
const poses = new Int16Array(bytes.buffer);
const frames = D.times.length;
const moving = D.moving.length;
const t0 = D.times[0];
const duration = D.times[frames - 1] - t0;

const view = document.getElementById('view');
const renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
renderer.setPixelRatio(1);
view.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0xdfe5ec);
scene.add(new THREE.HemisphereLight(0xffffff, 0x778899, 2.0));
const sun = new THREE.DirectionalLight(0xffffff, 1.8);
sun.position.set(1.0, -1.5, 3.0);
scene.add(sun);
const camera = new THREE.PerspectiveCamera(45, 1, 0.02, 60);
camera.up.set(0, 0, 1);

function geometry(g) {
  const [a, b, c] = g.size;
  switch (g.type) {
    case 'box': return new THREE.BoxGeometry(2 * a, 2 * b, 2 * c);
    case 'sphere': return new THREE.SphereGeometry(a, 24, 16);
    case 'ellipsoid': return new THREE.SphereGeometry(1, 24, 16).scale(a, b, c);
    case 'capsule': return new THREE.CapsuleGeometry(a, 2 * b, 6, 16).rotateX(Math.PI / 2);
    case 'cylinder': return new THREE.CylinderGeometry(a, a, 2 * b, 24).rotateX(Math.PI / 2);
    case 'plane': return new THREE.PlaneGeometry(2 * a, 2 * b);
  }
  throw new Error('unknown geom type ' + g.type);
}
const setQuat = (o, q) => o.quaternion.set(q[1], q[2], q[3], q[0]);
const categories = {robot: [], human: [], object: [], scene: []};
const groups = D.bodies.map((body) => {
  const group = new THREE.Group();
  for (const g of body.geoms) {
    const colour = new THREE.Color().setRGB(g.rgba[0], g.rgba[1], g.rgba[2], THREE.SRGBColorSpace);
    const material = new THREE.MeshLambertMaterial({color: colour, transparent: g.rgba[3] < 1, opacity: g.rgba[3]});
    const mesh = new THREE.Mesh(geometry(g), material);
    mesh.position.fromArray(g.pos);
    setQuat(mesh, g.quat);
    group.add(mesh);
  }
  if (body.pose) {
    group.position.fromArray(body.pose);
    setQuat(group, body.pose.slice(3));
  }
  scene.add(group);
  categories[body.category].push(group);
  return group;
});
const tcp = new THREE.Object3D();
tcp.position.fromArray(D.tcp.pos);
setQuat(tcp, D.tcp.quat);
groups[D.tcp.body].add(tcp);

// Contact points of the step, coloured by what the robot touches.
const contactColour = {human: 0xe0302a, environment: 0xf28e2b, object: 0xf2d02b};
const pointsByFrame = new Map();
for (const [f, x, y, z, kind] of D.contact_points) {
  if (!pointsByFrame.has(f)) pointsByFrame.set(f, []);
  pointsByFrame.get(f).push([x, y, z, kind]);
}
const markers = [];
const markerGeometry = new THREE.SphereGeometry(0.014, 12, 8);
function contactMarker(i) {
  while (markers.length <= i) {
    const m = new THREE.Mesh(markerGeometry, new THREE.MeshBasicMaterial({depthTest: false}));
    m.renderOrder = 10;
    scene.add(m);
    markers.push(m);
  }
  return markers[i];
}
const contactsByFrame = new Map();
for (const [f, part, other, kind, force] of D.contacts) {
  if (!contactsByFrame.has(f)) contactsByFrame.set(f, []);
  contactsByFrame.get(f).push(`${part} – ${other} (${kind}) ${force.toFixed(1)} N`);
}

// Orbit camera: drag turns, wheel zooms, shift-drag pans.
const orbit = {target: new THREE.Vector3(0.6, 0, 0.95), azimuth: -1.05, elevation: 0.42, distance: 2.3};
function placeCamera() {
  const c = Math.cos(orbit.elevation);
  camera.position.set(orbit.target.x + orbit.distance * c * Math.cos(orbit.azimuth),
                      orbit.target.y + orbit.distance * c * Math.sin(orbit.azimuth),
                      orbit.target.z + orbit.distance * Math.sin(orbit.elevation));
  camera.lookAt(orbit.target);
}
let drag = null;
view.addEventListener('pointerdown', (e) => { drag = {x: e.clientX, y: e.clientY, pan: e.shiftKey}; view.setPointerCapture(e.pointerId); });
view.addEventListener('pointerup', () => { drag = null; });
view.addEventListener('pointermove', (e) => {
  if (!drag) return;
  const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
  drag.x = e.clientX; drag.y = e.clientY;
  if (drag.pan) {
    const right = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 0);
    const up = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 1);
    const k = orbit.distance * 0.0015;
    orbit.target.addScaledVector(right, -dx * k).addScaledVector(up, dy * k);
  } else {
    orbit.azimuth -= dx * 0.008;
    orbit.elevation = Math.min(1.5, Math.max(-0.2, orbit.elevation + dy * 0.008));
  }
  draw();
});
view.addEventListener('wheel', (e) => {
  e.preventDefault();
  orbit.distance = Math.min(12, Math.max(0.3, orbit.distance * Math.exp(e.deltaY * 0.001)));
  draw();
}, {passive: false});

function resize() {
  renderer.setSize(view.clientWidth, view.clientHeight);
  camera.aspect = view.clientWidth / view.clientHeight;
  camera.updateProjectionMatrix();
}
function draw() {
  placeCamera();
  renderer.render(scene, camera);
}

// The separation of each step as a colour, and the timeline strip.
const separationColour = (f) => {
  const d = D.separation[f], sp = D.protective[f];
  if (d === null) return '#aaaaaa';
  if (d > D.monitored_distance) return '#59a14f';
  return d < sp ? '#e15759' : '#edc948';
};
const strip = document.getElementById('strip');
strip.width = frames;
strip.height = 1;
const stripContext = strip.getContext('2d');
for (let f = 0; f < frames; ++f) {
  stripContext.fillStyle = separationColour(f);
  stripContext.fillRect(f, 0, 1, 1);
}
const track = document.getElementById('track');
for (const e of D.events) {
  if (!['cue', 'act_start', 'act_end', 'contact_begin', 'warning'].includes(e.kind)) continue;
  const m = document.createElement('div');
  m.className = `marker ${e.kind} ${e.actor}`;
  m.style.left = `calc(${(100 * (e.t - t0) / Math.max(duration, 1e-9)).toFixed(3)}% - 1px)`;
  m.title = `${e.t.toFixed(2)} s: ${e.kind} ${e.name} ${e.detail}`;
  m.addEventListener('click', () => seek(e.t));
  track.appendChild(m);
}

const scrub = document.getElementById('scrub');
scrub.max = String(frames - 1);
const clock = document.getElementById('clock');
const separation = document.getElementById('separation');
const acts = document.getElementById('acts');
const contacts = document.getElementById('contacts');
let frame = 0;
function show(f) {
  frame = Math.max(0, Math.min(frames - 1, f));
  for (let i = 0; i < moving; ++i) {
    const o = (frame * moving + i) * 7;
    const g = groups[D.moving[i]];
    g.position.set(poses[o] / 1000, poses[o + 1] / 1000, poses[o + 2] / 1000);
    g.quaternion.set(poses[o + 4], poses[o + 5], poses[o + 6], poses[o + 3]).normalize();
  }
  const points = pointsByFrame.get(frame) || [];
  points.forEach(([x, y, z, kind], i) => {
    const m = contactMarker(i);
    m.position.set(x, y, z);
    m.material.color.setHex(contactColour[kind]);
    m.visible = true;
  });
  for (let i = points.length; i < markers.length; ++i) markers[i].visible = false;
  const t = D.times[frame];
  clock.textContent = `t = ${t.toFixed(2)} s of ${D.times[frames - 1].toFixed(2)} s (step ${frame})`;
  const d = D.separation[frame];
  separation.textContent = d === null ? 'no human' : `d = ${d.toFixed(3)} m, S_p = ${D.protective[frame].toFixed(3)} m`;
  separation.style.background = separationColour(frame);
  const running = new Map();
  for (const e of D.events) {
    if (e.t > t + 1e-9) break;
    if (e.kind === 'act_start') running.set(e.name.replace(/\.start$/, ''), e.actor);
    if (e.kind === 'act_end') running.delete(e.name.replace(/\.end$/, ''));
  }
  acts.textContent = running.size ? 'acts: ' + [...running].map(([n, a]) => `${n} (${a})`).join(', ') : 'no act running';
  contacts.textContent = (contactsByFrame.get(frame) || []).join('; ');
  scrub.value = String(frame);
  tcp.updateWorldMatrix(true, false);
  draw();
}
function frameAt(t) {
  let lo = 0, hi = frames - 1;
  while (lo < hi) {
    const mid = (lo + hi) >> 1;
    if (D.times[mid] < t) lo = mid + 1; else hi = mid;
  }
  return lo > 0 && t - D.times[lo - 1] < D.times[lo] - t ? lo - 1 : lo;
}
function seek(t) { show(frameAt(t)); return D.times[frame]; }

let playing = false, last = 0, clockTime = 0;
const playButton = document.getElementById('play');
const speed = document.getElementById('speed');
function tick(now) {
  if (!playing) return;
  clockTime += (now - last) / 1000 * Number(speed.value);
  last = now;
  if (clockTime >= D.times[frames - 1]) { clockTime = D.times[frames - 1]; pause(); }
  const f = frameAt(clockTime);
  if (f !== frame) show(f);
  if (playing) requestAnimationFrame(tick);
}
function play() {
  if (frame === frames - 1) show(0);
  playing = true; clockTime = D.times[frame]; last = performance.now();
  playButton.textContent = '❚❚ pause';
  requestAnimationFrame(tick);
}
function pause() { playing = false; playButton.textContent = '▶ play'; }
playButton.addEventListener('click', () => (playing ? pause() : play()));
scrub.addEventListener('input', () => { pause(); show(Number(scrub.value)); });
window.addEventListener('resize', () => { resize(); draw(); });

resize();
show(0);
window.hribenchReplay = {
  ready: true,
  seek,
  time: () => D.times[frame],
  duration: () => duration,
  frames: () => frames,
  endEffectorPosition: () => { tcp.updateWorldMatrix(true, false); return new THREE.Vector3().setFromMatrixPosition(tcp.matrixWorld).toArray(); },
  contactPoints: () => markers.filter((m) => m.visible).map((m) => m.position.toArray()),
  setVisible: (category, on) => { for (const g of categories[category]) g.visible = on; draw(); },
  play,
  pause,
};
)JS";

}  // namespace

model::Model model_of_log(const eval::EpisodeLog& log) {
  const std::vector<gen::TaskFile> tasks = gen::task_catalogue();
  const auto task = std::find_if(tasks.begin(), tasks.end(), [&](const gen::TaskFile& t) { return t.name == log.task; });
  if (task == tasks.end()) {
    throw core::InputError("the episode's task", "a task of " + (core::data_root() / "tasks").string(),
                           "'" + log.task + "'");
  }
  const script::EpisodeSpec spec =
      script::sample(script::load_scenario(core::resolve_data_path(task->script).string()), log.seed, log.robot);
  if (const std::string hash = script::spec_hash(spec); hash != log.spec_hash) {
    throw core::InputError(task->script,
                           fmt::format("the script the episode ran (seed {} -> spec hash {})", log.seed, log.spec_hash),
                           "spec hash " + hash + ": the script changed since the run");
  }
  return model::build(eval::scene_spec_from_episode(spec));
}

ThreeJs load_three_js(const fs::path& root) {
  const fs::path build = root / "node_modules" / "three" / "build";
  return ThreeJs{strip_comment_lines(read_text(build / "three.core.js")),
                 strip_comment_lines(read_text(build / "three.module.js"))};
}

std::string replay_html(const model::Model& model, const eval::EpisodeLog& log, const ThreeJs& three,
                        const eval::MetricConstants& constants) {
  HRIB_CHECK(!log.steps.empty()) << "a log without steps";
  const std::string title = fmt::format("{} seed {}, {} ({:.2f} s, {})", log.task, log.seed, log.policy,
                                        log.duration(), core::to_string(log.status));
  std::string escaped_title;
  for (const char c : title) escaped_title += c == '<' ? std::string("&lt;") : c == '&' ? std::string("&amp;") : std::string(1, c);
  return fmt::format(kPage, fmt::arg("title", escaped_title),
                     fmt::arg("data", script_json(episode_data(model, log, constants))),
                     fmt::arg("three_core", raw_script_text(three.core, "three.core.js")),
                     fmt::arg("three_module", raw_script_text(three.module, "three.module.js")),
                     fmt::arg("app", kApp));
}

fs::path write_replay_html(const fs::path& run, std::string_view episode, const fs::path& out) {
  const fs::path log_path = eval::find_episode_log(run, episode, "EPISODE");
  const ThreeJs three = load_three_js(core::data_root());
  const eval::EpisodeLog log = eval::load_episode_log(log_path);
  if (log.steps.empty()) throw core::InputError(log_path.string(), "a log with steps", "none");
  std::error_code ec;
  const eval::MetricConstants constants =
      fs::is_regular_file(run / "results.json", ec) ? eval::load_run(run).info.constants : eval::MetricConstants{};
  const model::Model model = model_of_log(log);
  const fs::path path = out.empty() ? eval::replay_file(run, log_path.stem().string()) : out;
  if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
  core::write_file_atomically(path, replay_html(model, log, three, constants));
  return path;
}

}  // namespace hribench::io
