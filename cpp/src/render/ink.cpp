// The density a tuft's footprint reaches the paper at, from its nodes' wetness (seed "Ink loading").
#include <algorithm>
#include <cmath>

#include "brushwork/render.hpp"

namespace brushwork {

double ink_density(const TuftFrame& tuft) {
  // the ink reaches the paper at full density while some node that touches it holds a tenth of
  // its load, then fades with the wettest one (a drying brush breaks up through the dry map
  // first, and greys only when nearly empty)
  const std::vector<float> p = node_pressure(tuft.sections);
  double touching = 0.0, all = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double d = std::clamp(10.0 * tuft.wetness[static_cast<Eigen::Index>(i)], 0.0, 1.0);
    all = std::max(all, d);
    if (p[i] > 0.0f) touching = std::max(touching, d);
  }
  return touching > 0.0 ? touching : all;
}

}  // namespace brushwork
