// Loops (mm) to and from Clipper's integer paths (1 nm units).
#pragma once

#include <polyclipping/clipper.hpp>

#include "brushwork/brush.hpp"

namespace brushwork::clip {

constexpr double kUnitsPerMm = 1e6;  // Clipper's integer coordinates: 1 nm

ClipperLib::Path to_path(const Eigen::Ref<const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>>& loop);
Loops to_loops(const ClipperLib::Paths& paths);
ClipperLib::Paths to_paths(const Loops& loops);
// the union (winding > 0) of paths
ClipperLib::Paths unite(const ClipperLib::Paths& paths);

}  // namespace brushwork::clip
