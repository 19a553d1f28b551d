// The geometry of a tuft at a deposit, as the renderer and the ink take it.
#include "brushwork/tuft_frame.hpp"

#include <algorithm>
#include <cmath>

namespace brushwork {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr int kPressureSamples = 32;      // points around a section where its lowest point is looked for
constexpr double kMinMinorRadius = 1e-3;  // mm: the least minor radius c a node's pressure is taken over
}  // namespace

std::vector<float> node_pressure(const std::vector<Section>& sections) {
  std::vector<float> p(sections.size(), 0.0f);
  for (std::size_t i = 0; i < sections.size(); ++i) {
    const Section& s = sections[i];
    // lowest point of the two half ellipses, sampled around
    double zmin = s.center.z();
    for (int k = 0; k < kPressureSamples; ++k) {
      const double t = 2.0 * kPi * k / kPressureSamples;
      const double ct = std::cos(t), st = std::sin(t);
      const double z = s.center.z() + (ct >= 0 ? s.a_plus : s.a_minus) * ct * s.u.z() + s.c * st * s.w.z();
      zmin = std::min(zmin, z);
    }
    p[i] = static_cast<float>(std::clamp(-zmin / std::max(s.c, kMinMinorRadius), 0.0, 1.0));
  }
  return p;
}

namespace {

bool same_sections(const std::vector<Section>& a, const std::vector<Section>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Section &p = a[i], &q = b[i];
    if (p.center != q.center || p.u != q.u || p.w != q.w || p.n != q.n || p.a_plus != q.a_plus ||
        p.a_minus != q.a_minus || p.c != q.c)
      return false;
  }
  return true;
}

}  // namespace

Loops footprint_of(const std::vector<Section>& sections, const MeshOptions& opt) {
  // the last few asked for, kept (one a tuft): a frame's footprint is asked for by the writer that
  // measures it and again by the paper's ledger that spends the ink
  struct Kept {
    std::vector<Section> sections;
    MeshOptions opt;
    Loops loops;
  };
  constexpr std::size_t kKept = 8;
  thread_local std::vector<Kept> kept;
  for (const Kept& k : kept)
    if (k.opt.rings_per_segment == opt.rings_per_segment && k.opt.around == opt.around &&
        same_sections(k.sections, sections))
      return k.loops;
  Loops loops = footprint_loops(sweep_surface(sections, opt));
  if (kept.size() == kKept) kept.erase(kept.begin());
  kept.push_back(Kept{sections, opt, loops});
  return loops;
}

Loops own_footprint(const TuftFrame& tuft) { return footprint_of(tuft.sections); }

}  // namespace brushwork
