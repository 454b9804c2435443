#include "sim/contact.h"

#include <fmt/format.h>

#include <algorithm>
#include <utility>

#include "core/errors.h"

namespace hribench::sim {
namespace {

using model::GeomOwner;

// Ordering of parties within a contact: robot, object, human, the rest.
int rank(const ContactParty& p) {
  if (p.is_robot()) return 0;
  if (p.owner == GeomOwner::kObject) return 1;
  if (p.is_human()) return 2;
  return 3;
}

ContactParty party_of(const model::Model& model, int geom) {
  const model::GeomTag& tag = model.geom_tags[static_cast<size_t>(geom)];
  return {geom, tag.owner, tag.index, tag.region};
}

}  // namespace

void find_contacts(const model::Model& model, const mjModel& m, const mjData& d,
                   std::vector<Contact>* out) {
  HRIB_CHECK(out != nullptr);
  HRIB_CHECK(static_cast<int>(model.geom_tags.size()) == m.ngeom)
      << "geom_tags has " << model.geom_tags.size() << " entries for " << m.ngeom << " geoms";
  out->clear();
  for (int i = 0; i < d.ncon; ++i) {
    const mjContact& con = d.contact[i];
    if (con.exclude != 0 || con.efc_address < 0) continue;
    mjtNum force[6];
    mj_contactForce(&m, &d, i, force);
    Contact c;
    c.a = party_of(model, con.geom1);
    c.b = party_of(model, con.geom2);
    // The contact frame's normal (first row) points from geom1 to geom2.
    c.normal_W = core::Vec3(con.frame[0], con.frame[1], con.frame[2]);
    if (rank(c.b) < rank(c.a)) {
      std::swap(c.a, c.b);
      c.normal_W = -c.normal_W;
    }
    c.normal_force = std::max(0.0, force[0]);
    c.distance = con.dist;
    c.position_W = core::Vec3(con.pos[0], con.pos[1], con.pos[2]);
    out->push_back(c);
  }
}

void find_contacts(const model::Model& model, const Data& data, std::vector<Contact>* out) {
  find_contacts(model, *model.m(), *data.mj, out);
}

std::vector<Contact> find_contacts(const model::Model& model, const mjData& d) {
  std::vector<Contact> out;
  out.reserve(static_cast<size_t>(d.ncon));
  find_contacts(model, *model.m(), d, &out);
  return out;
}

std::vector<Contact> find_contacts(const model::Model& model, const Data& data) {
  return find_contacts(model, *data.mj);
}

std::string party_name(const model::Model& model, const ContactParty& party) {
  switch (party.owner) {
    case GeomOwner::kRobotLink:
      return fmt::format("link{}", party.index);
    case GeomOwner::kRobotHand:
      return "hand";
    case GeomOwner::kRobotFinger:
      return party.index == 0 ? "left_finger" : "right_finger";
    case GeomOwner::kHuman: {
      const auto i = static_cast<size_t>(party.index);
      const std::string_view capsule =
          i < model.human_capsules.size() ? model.human_capsules[i].name : "?";
      return fmt::format("human:{} ({})", capsule, human::to_string(party.region));
    }
    case GeomOwner::kObject: {
      const auto i = static_cast<size_t>(party.index);
      return fmt::format("object:{}", i < model.objects.size() ? model.objects[i].name : "?");
    }
    case GeomOwner::kTable:
      return "table";
    case GeomOwner::kFloor:
      return "floor";
    case GeomOwner::kPlatform:
      return "platform";
    case GeomOwner::kOther:
      break;
  }
  const char* name = mj_id2name(model.m(), mjOBJ_GEOM, party.geom);
  return name != nullptr ? std::string(name) : fmt::format("geom{}", party.geom);
}

std::string_view to_string(ContactGrade grade) {
  switch (grade) {
    case ContactGrade::kNoForce:
      return "no_force";
    case ContactGrade::kWithinLimit:
      return "within_limit";
    case ContactGrade::kAboveQuasiStatic:
      return "above_quasi_static";
    case ContactGrade::kCritical:
      return "critical";
  }
  return "?";
}

ContactGrade grade_contact(human::BodyRegion region, double normal_force_N, double transient_factor) {
  const double limit = human::quasi_static_force_limit(region);
  if (normal_force_N > transient_factor * limit) return ContactGrade::kCritical;
  if (normal_force_N > limit) return ContactGrade::kAboveQuasiStatic;
  if (normal_force_N > 0.0) return ContactGrade::kWithinLimit;
  return ContactGrade::kNoForce;
}

void human_contact_loads(const std::vector<Contact>& contacts, double transient_factor,
                         std::vector<HumanContactLoad>* out) {
  HRIB_CHECK(out != nullptr);
  out->clear();
  for (const Contact& c : contacts) {
    if (!c.robot_human()) continue;
    // Keep `out` sorted by human geom id; add to the geom's entry.
    auto it = std::lower_bound(
        out->begin(), out->end(), c.b.geom,
        [](const HumanContactLoad& load, int geom) { return load.human_geom < geom; });
    if (it == out->end() || it->human_geom != c.b.geom) {
      it = out->insert(it, HumanContactLoad{c.b.geom, c.b.region, 0.0, ContactGrade::kNoForce});
    }
    it->normal_force += c.normal_force;
  }
  for (HumanContactLoad& load : *out) load.grade = grade_contact(load.region, load.normal_force, transient_factor);
}

ContactGrade worst_grade(const std::vector<HumanContactLoad>& loads) {
  ContactGrade worst = ContactGrade::kNoForce;
  for (const HumanContactLoad& load : loads) worst = std::max(worst, load.grade);
  return worst;
}

}  // namespace hribench::sim
