#include "brushwork/scene.hpp"

#include <limits>
#include <stdexcept>

#include "render/checks.hpp"

namespace brushwork {
namespace {

constexpr double kAny = std::numeric_limits<double>::infinity();  // no upper bound

SceneSlot feature(const char* name, bool SceneFeatures::*p, const char* define, const char* doc) {
  return SceneSlot{name, "-", "bool", 0.0, 0.0, 1.0, false, false, false, nullptr, define, doc,
                   p, nullptr, nullptr, nullptr};
}
SceneSlot real(const char* name, const char* unit, double value, double lo, double hi, bool open_low,
               const char* expected, double SceneFeatures::*p, const char* doc) {
  return SceneSlot{name, unit, "float", value, lo, hi, open_low, false, false, expected, "", doc,
                   nullptr, p, nullptr, nullptr};
}
SceneSlot count(const char* name, int value, int lo, int hi, int SceneFeatures::*p, const char* doc) {
  return SceneSlot{name, "-", "int", static_cast<double>(value), static_cast<double>(lo),
                   static_cast<double>(hi), false, false, false, "", "", doc, nullptr, nullptr, p, nullptr};
}

std::vector<SceneSlot> feature_rows() {
  using S = SceneFeatures;
  return {
      // seed "Fine bristle effect": the tip parts into bristle groups
      feature("split_map", &S::split_map, "USE_SPLIT", "the tip parts into bristle groups"),
      // seed "Dry brush": bristle-clump field thresholded by moisture, speed and pressure
      feature("dry_map", &S::dry_map, "USE_DRY", "dry streaks: a bristle-clump field thresholded by moisture, speed and pressure"),
      // seed "Grain texture": paper height field thresholded when dry
      feature("grain", &S::grain, "USE_GRAIN", "paper grain: a height field thresholded when dry"),
      // seed "Soaked brush": tip expanded, split map dilated, drains
      feature("soaked_tip", &S::soaked_tip, "USE_SOAK", "a soaked tip: expanded, its split map dilated, draining"),
      // seed "Ink loading": colour gradient along the spine
      feature("color_ramp", &S::color_ramp, "USE_RAMP", "a colour gradient along the spine"),
      // ink subtracted from the brush (off: constant ink level)
      feature("depletion", &S::depletion, "USE_DEPLETION", "ink spent from the brush (off: a constant ink level)")};
}

std::vector<SceneSlot> threshold_rows() {
  using S = SceneFeatures;
  const char* unit01 = "0 < value <= 1";
  const char* positive = "a finite positive number";
  return {
      real("dry_onset", "-", 0.6, 0.0, 1.0, true, unit01, &S::dry_onset,
           "wetness below which the dry map opens streaks"),
      real("dry_pressure", "-", 0.5, 0.0, 10.0, false, "0..10", &S::dry_pressure,
           "how much node pressure closes dry streaks again"),
      real("grain_onset", "-", 0.4, 0.0, 1.0, true, unit01, &S::grain_onset,
           "wetness below which paper grain shows"),
      real("grain_pressure", "-", 0.5, 0.0, 10.0, false, "0..10", &S::grain_pressure,
           "how much pressure presses ink into the grain's valleys"),
      // the grain's lattice cell
      real("grain_mm", "mm", 0.25, 0.0, kAny, true, positive, &S::grain_mm, "size of the paper grain's features"),
      // split and dry fields; the dry field runs 50 of them along the stroke
      real("streak_mm", "mm", 0.3, 0.0, kAny, true, positive, &S::streak_mm,
           "width of a bristle streak across the stroke (split and dry fields)"),
      real("dry_speed", "-", 0.0, 0.0, 10.0, false, "0..10", &S::dry_speed,
           "dryness added per mm the footprint travels per frame"),
      real("soak_expand", "-", 0.25, 0.0, 2.0, false, "0..2", &S::soak_expand,
           "radial growth of a soaked tip at full excess moisture"),
      real("soak_shift", "-", 0.35, 0.0, 1.0, false, "0..1", &S::soak_shift,
           "split map scaled toward the tip at full excess moisture"),
      real("soak_drain_mm", "mm", 40.0, 0.0, kAny, true, positive, &S::soak_drain_mm,
           "travel in contact over which excess moisture falls by 1/e"),
      // ink flows to the tip
      real("capillary", "-", 0.2, 0.0, 1.0, false, "0..1", &S::capillary,
           "depletion: per frame, each node's wetness moves this far toward the tuft's mean")};
}

std::vector<SceneSlot> mesh_rows() {
  using S = SceneFeatures;
  SceneSlot seed{"seed", "-", "seed", 1.0, 0.0, 4294967295.0, false, false, false, nullptr, "",
                 "seed of the procedural split, dry and grain fields", nullptr, nullptr, nullptr, &S::seed};
  // rings per segment and vertices around are chosen per brush (longest segment and belly
  // circumference over mesh_mm), capped by mesh_rings and mesh_around; the same at every output
  // size from 3 px to mesh_mm up (5 px/mm), which only samples the surface, its edges kept at 3 px
  // below.  `brushwork bench render` sweeps it (ink error against time)
  SceneSlot mesh_mm = real("mesh_mm", "mm", 0.6, 0.05, 10.0, false, "0 or 0.05..10", &S::mesh_mm,
                           "the render mesh is this fine (segment and belly circumference over it), up to "
                           "the two caps, at every output size from 3 px to mesh_mm up; 0: the caps");
  mesh_mm.zero_ok = true;
  // on a software rasteriser 4x is ~2.5x the time of 1x; 1x loses the faint ink of footprints
  // thinner than a pixel (see Paper::samples); the device's maximum at most
  SceneSlot samples = count("samples", 4, 1, 8, &S::samples,
                            "multisampling of the stroke layer: 1, 2, 4 (default) or 8; 1 is ~2.5x faster "
                            "on a software renderer");
  samples.pow2 = true;
  samples.expected = "1, 2, 4 or 8";
  return {seed,
          count("mesh_rings", 6, 1, 64, &S::mesh_rings, "rings per spine segment of the swept surface, at most"),
          count("mesh_around", 48, 8, 512, &S::mesh_around, "vertices around one ring, at most"),
          mesh_mm, samples};
}

std::vector<SceneSlot> make_table() {
  std::vector<SceneSlot> t = feature_rows();
  for (const auto& rows : {threshold_rows(), mesh_rows()}) t.insert(t.end(), rows.begin(), rows.end());
  return t;
}

void set_value(SceneFeatures& s, const SceneSlot& slot, double v) {
  if (slot.flag) s.*slot.flag = v != 0.0;
  if (slot.real) s.*slot.real = v;
  if (slot.count) s.*slot.count = static_cast<int>(v);
  if (slot.seed) s.*slot.seed = static_cast<std::uint32_t>(v);
}

// a count in lo..hi (a power of two when pow2), the message naming the field
void check_count(const std::string& name, int v, const SceneSlot& slot) {
  const bool ok = v >= slot.lo && v <= slot.hi && (!slot.pow2 || (v & (v - 1)) == 0);
  if (ok) return;
  const std::string expected = *slot.expected ? std::string(slot.expected)
                                              : std::to_string(static_cast<int>(slot.lo)) + ".." +
                                                    std::to_string(static_cast<int>(slot.hi));
  throw std::invalid_argument(name + " = " + std::to_string(v) + ": expected " + expected);
}

}  // namespace

const std::vector<SceneSlot>& scene_slots() {
  static const std::vector<SceneSlot> table = make_table();
  return table;
}

SceneFeatures::SceneFeatures() {
  for (const SceneSlot& slot : scene_slots()) set_value(*this, slot, slot.value);
}

double scene_value(const SceneFeatures& s, const SceneSlot& slot) {
  if (slot.flag) return s.*slot.flag ? 1.0 : 0.0;
  if (slot.real) return s.*slot.real;
  if (slot.count) return s.*slot.count;
  return s.*slot.seed;
}

void SceneFeatures::validate() const {
  for (const SceneSlot& slot : scene_slots()) {
    if (!slot.expected) continue;  // any value
    const std::string name = std::string("scene.") + slot.name;
    if (slot.count) check_count(name, this->*slot.count, slot);
    if (slot.real && !(slot.zero_ok && this->*slot.real == 0.0))
      checks::in_range(name, this->*slot.real, slot.lo, slot.hi, slot.open_low, slot.expected);
  }
}

std::vector<std::string> scene_defines(const SceneFeatures& s) {
  std::vector<std::string> defines;
  for (const SceneSlot& slot : scene_slots())
    if (slot.flag && s.*slot.flag) defines.push_back(slot.define);
  return defines;
}

}  // namespace brushwork
