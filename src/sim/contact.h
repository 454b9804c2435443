#pragma once
// The contact query: who touches whom, where, and how hard, from mjData.contact and
// mj_contactForce; and the grading of a human contact against ISO/TS 15066
// (docs/metrics.md, HCS: above the quasi-static limit; above the transient limit, 2x, it is
// critical).
//
// Forces are the constraint forces of the last mj_forward / mj_step (N); positions are in the
// world frame (m). Only contacts that MuJoCo made active constraints are listed
// (mjContact.exclude == 0 and efc_address >= 0).

#include <string>
#include <string_view>
#include <vector>

#include <mujoco/mujoco.h>

#include "core/math.h"
#include "human/skeleton.h"
#include "model/model.h"
#include "sim/data.h"

namespace hribench::sim {

// One side of a contact: the geom and what it belongs to (from model::Model::geom_tags).
struct ContactParty {
  int geom = -1;                                  // MuJoCo geom id
  model::GeomOwner owner = model::GeomOwner::kOther;
  int index = -1;                                 // as model::GeomTag::index
  human::BodyRegion region = human::BodyRegion::kTorso;  // meaningful only for kHuman

  bool is_robot() const {
    return owner == model::GeomOwner::kRobotLink || owner == model::GeomOwner::kRobotHand ||
           owner == model::GeomOwner::kRobotFinger;
  }
  bool is_human() const { return owner == model::GeomOwner::kHuman; }
};

struct Contact {
  // Ordered so that `a` is the more "active" party: robot part, then object, then human, then
  // table / floor / platform / other. `b` is the other party (for two parties of the same
  // rank, MuJoCo's geom1 / geom2 order).
  ContactParty a;
  ContactParty b;
  double normal_force = 0;  // N, >= 0 (the normal component of mj_contactForce)
  double distance = 0;      // m, mjContact.dist: signed, negative = penetration depth
  core::Vec3 position_W = core::Vec3::Zero();  // contact point (midway between the surfaces)
  core::Vec3 normal_W = core::Vec3::Zero();    // unit normal, pointing from a toward b

  bool involves_human() const { return a.is_human() || b.is_human(); }
  bool robot_human() const { return a.is_robot() && b.is_human(); }
  // The human party (nullptr if none).
  const ContactParty* human() const { return b.is_human() ? &b : a.is_human() ? &a : nullptr; }
};

// Fills `out` (cleared first) with the active contacts of `d`, in MuJoCo's contact order.
// Allocation-free once `out` has capacity for d.ncon contacts.
void find_contacts(const model::Model& model, const mjModel& m, const mjData& d,
                   std::vector<Contact>* out);
// The same on a running episode's Data: after step() these are the contacts and forces that
// the step solved (those of the state before integration); after forward() the current ones.
void find_contacts(const model::Model& model, const Data& data, std::vector<Contact>* out);
// Convenience (allocates).
std::vector<Contact> find_contacts(const model::Model& model, const mjData& d);
std::vector<Contact> find_contacts(const model::Model& model, const Data& data);

// A readable name of a party, e.g. "link3", "hand", "left_finger", "human:right_hand (hand)",
// "object:cube0", "table", "floor".
std::string party_name(const model::Model& model, const ContactParty& party);

// ISO/TS 15066 grade of a force on a body region.
enum class ContactGrade {
  kNoForce,          // normal force == 0 (touching without pressing)
  kWithinLimit,      // 0 < F <= quasi-static limit
  kAboveQuasiStatic, // quasi-static limit < F <= transient limit
  kCritical,         // F > transient limit (transient_factor x quasi-static limit)
};
std::string_view to_string(ContactGrade grade);  // "no_force", "within_limit", ...
// Grade of `normal_force_N` on `region`: the quasi-static limit is
// human::quasi_static_force_limit(region), the transient limit `transient_factor` times
// it. The one definition of a critical contact (eval's metrics grade with it too).
ContactGrade grade_contact(human::BodyRegion region, double normal_force_N, double transient_factor);

// The force one robot presses on one human geom at this instant: the sum of the normal forces
// of all robot contacts on that geom (MuJoCo may report several points per geom pair), graded.
struct HumanContactLoad {
  int human_geom = -1;
  human::BodyRegion region = human::BodyRegion::kTorso;
  double normal_force = 0;  // N, summed over the contact points
  ContactGrade grade = ContactGrade::kNoForce;
};
// Fills `out` (cleared first) with one load per human geom touched by the robot, in human geom
// id order, graded with grade_contact(.., transient_factor). Allocation-free once `out` has
// capacity (one entry per touched human geom).
void human_contact_loads(const std::vector<Contact>& contacts, double transient_factor,
                         std::vector<HumanContactLoad>* out);
// The worst grade among `loads` (kNoForce if empty).
ContactGrade worst_grade(const std::vector<HumanContactLoad>& loads);

}  // namespace hribench::sim
