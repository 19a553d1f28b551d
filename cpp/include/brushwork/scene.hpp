// What a scene uses (DESIGN "scene.py"): the seed's rendering features, switched on one by one,
// and their settings, all written once in scene_slots().  Each feature off is neither computed on
// the CPU nor compiled into the footprint shader (it becomes an absent #define).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace brushwork {

// The fields are documented, ranged and defaulted by their rows in scene_slots().
struct SceneFeatures {
  SceneFeatures();  // every field at its row's default

  // features (seed "Fine bristle effect", "Dry brush", "Grain texture", "Soaked brush",
  // "Ink loading" twice)
  bool split_map, dry_map, grain, soaked_tip, color_ramp, depletion;
  // thresholds (dimensionless, wetness and pressure in [0, 1]) and sizes
  double dry_onset, dry_pressure, grain_onset, grain_pressure, grain_mm, streak_mm, dry_speed;
  double soak_expand, soak_shift, soak_drain_mm, capillary;
  std::uint32_t seed;
  // the render mesh and the stroke layer's multisampling
  int mesh_rings, mesh_around;
  double mesh_mm;
  int samples;

  void validate() const;  // std::invalid_argument naming the field
};

// One row of the scene's table: a feature switch (kind "bool", with the #define that compiles it
// into the footprint shader) or a setting (kind "float", "int" or "seed") with its unit, default and
// range (lo excluded when open_low; 0 also allowed when zero_ok; a power of two when pow2),
// `expected` being the range as a message says it (null: any value).  Exactly one member pointer
// is set, the one of its kind.
struct SceneSlot {
  const char* name;
  const char* unit;
  const char* kind;
  double value;  // the default
  double lo, hi;
  bool open_low, zero_ok, pow2;
  const char* expected;
  const char* define;  // features only ("" for a setting)
  const char* doc;
  bool SceneFeatures::*flag;
  double SceneFeatures::*real;
  int SceneFeatures::*count;
  std::uint32_t SceneFeatures::*seed;
};
const std::vector<SceneSlot>& scene_slots();

// the field of `slot` in `s`, as a double
double scene_value(const SceneFeatures& s, const SceneSlot& slot);
// the footprint shader's #defines for the features `s` switches on, in the table's order
std::vector<std::string> scene_defines(const SceneFeatures& s);

}  // namespace brushwork
