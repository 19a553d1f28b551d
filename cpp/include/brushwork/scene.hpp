// What a scene uses: the seed's rendering features, switched on one by one, and their thresholds.
#pragma once

#include <cstdint>

namespace brushwork {

// What a scene uses (DESIGN "scene.py").  Each feature off is neither computed on the CPU nor
// compiled into the footprint shader (it becomes an absent #define).
struct SceneFeatures {
  bool split_map = false;    // seed "Fine bristle effect": the tip parts into bristle groups
  bool dry_map = false;      // seed "Dry brush": bristle-clump field thresholded by moisture,
                             // speed and pressure
  bool grain = false;        // seed "Grain texture": paper height field thresholded when dry
  bool soaked_tip = false;   // seed "Soaked brush": tip expanded, split map dilated, drains
  bool color_ramp = false;   // seed "Ink loading": colour gradient along the spine
  bool depletion = false;    // ink subtracted from the brush (off: constant ink level)

  // thresholds (dimensionless, wetness and pressure in [0, 1])
  double dry_onset = 0.6;       // wetness below which the dry map starts to open streaks
  double dry_pressure = 0.5;    // how much pressure closes the streaks again
  double grain_onset = 0.4;     // wetness below which paper grain shows
  double grain_pressure = 0.5;  // how much pressure presses ink into the grain's valleys
  double grain_mm = 0.25;       // mm: the size of the paper grain's features (its lattice cell)
  double streak_mm = 0.3;       // mm: the width of a bristle streak across the stroke (split
                                // and dry fields; the dry field runs 50 of them along the stroke)
  double dry_speed = 0.0;       // dryness added per mm of the footprint's travel per deposit
  double soak_expand = 0.25;    // radial growth of the tip at full excess moisture (fraction)
  double soak_shift = 0.35;     // split map scaled toward the tip at full excess moisture
  double soak_drain_mm = 40.0;  // travel in contact over which excess moisture falls by 1/e
  double capillary = 0.2;       // depletion: fraction of the way each node's wetness moves
                                // toward the tuft's mean per frame (ink flows to the tip)
  std::uint32_t seed = 1;       // procedural fields (split, dry, grain)
  int mesh_rings = 6;           // rings per spine segment of the swept surface (at most)
  int mesh_around = 48;         // vertices around one ring (at most)
  double mesh_mm = 0.6;         // mm: the render mesh is as fine as this on the paper, no finer:
                                // rings per segment and vertices around are chosen per brush
                                // (longest segment and belly circumference over mesh_mm),
                                // capped by the two above; the same at every output size from
                                // 3 px to mesh_mm up (5 px/mm), which only samples the surface,
                                // its edges kept at 3 px below.  0: always the caps.
                                // `brushwork bench render` sweeps it (ink error against time)
  int samples = 4;              // multisampling of the stroke layer: 1 (none), 2, 4 or 8 (the
                                // device's maximum at most).  On a software rasteriser 4x is
                                // ~2.5x the time of 1x; 1x loses the faint ink of footprints
                                // thinner than a pixel (see Paper::samples)

  void validate() const;  // std::invalid_argument naming the field
};

}  // namespace brushwork
