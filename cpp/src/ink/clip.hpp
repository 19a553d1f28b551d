// Loops (mm) to and from Clipper's integer paths (1 nm units).
#pragma once

#include <polyclipping/clipper.hpp>

#include "brushwork/tuft_frame.hpp"

namespace brushwork::clip {

constexpr double kUnitsPerMm = 1e6;  // Clipper's integer coordinates: 1 nm

ClipperLib::Path to_path(const Eigen::Ref<const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>>& loop);
Loops to_loops(const ClipperLib::Paths& paths);
ClipperLib::Paths to_paths(const Loops& loops);
// the union (winding > 0) of paths
ClipperLib::Paths unite(const ClipperLib::Paths& paths);
// the region closed and opened by a disc of radius r mm (grown by r, shrunk by 2 r, grown by r):
// slits and slivers thinner than 2 r go, corners round to radius r, the rest stays
ClipperLib::Paths clean(const ClipperLib::Paths& paths, double r_mm);

}  // namespace brushwork::clip
