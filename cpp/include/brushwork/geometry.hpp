// Swept-surface geometry of one tuft (seed "Brush surface", Figures 2-3) and its footprint
// on the paper (seed "Ink depositing": the orthographic projection of the part of the surface
// below the paper).  Everything is in millimetres, paper at z = 0, z up.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace brushwork {

using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;

// One elliptic cross section Omega_i (seed Figure 3): two half ellipses sharing the minor
// radius c.  The section lies in the plane spanned by u and w (the joint-bisecting plane);
// n is the unit normal of that plane pointing from root toward tip.  (u, w, n) are orthonormal
// but their handedness is not promised: code must not rely on it.
struct Section {
  Vec3 center = Vec3::Zero();  // mm: O_i, moved toward the paper by r_i - c_i when spread (Brush::sections)
  Vec3 u = Vec3::UnitX();      // unit major axis = lateral line of N_i
  Vec3 w = Vec3::UnitY();      // unit minor axis, in the bisecting plane, w perpendicular to u
  Vec3 n = -Vec3::UnitZ();     // unit normal of the section plane, toward the tip
  double a_plus = 1.0;         // major radius on the +u side (a + r_lat), mm
  double a_minus = 1.0;        // major radius on the -u side (b + r_lat), mm
  double c = 1.0;              // common minor radius, mm
};

// Triangle mesh of the swept surface.  Row-major so numpy views it without a copy.
struct SurfaceMesh {
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> vertices;  // (V, 3) mm
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> faces;        // (F, 3) vertex indices, outward CCW
  Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> uv;        // (V, 2) (along spine in [0,1], around in [0,1])
};

struct MeshOptions {
  int rings_per_segment = 8;  // sub-sections swept between two consecutive Omega_i
  int around = 32;            // vertices around one ring
};

// Sweep the sections (root first, tip last; at least 2) into a closed triangle mesh: rings of
// `around` vertices, a root cap and a tip apex, outward-facing triangles.
SurfaceMesh sweep_surface(const std::vector<Section>& sections, const MeshOptions& opt);

// Footprint: closed loops where the mesh crosses the plane z = 0, projected to (x, y) mm.
// Outer loops are counter-clockwise seen from +z, holes clockwise; the signed areas add up
// to the footprint area.  Empty when nothing is below the paper.
std::vector<Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>> footprint_loops(
    const SurfaceMesh& mesh);

// The footprint as the seed defines it ("the orthogonal projection of the penetrating portion
// onto the paper plane"): closed loops around the projection of the mesh's part below z = 0, in
// (x, y) mm, the region to the left of each (outer loops counter-clockwise).  Its outline is made
// of two kinds of line, each found on every face as the z = 0 section is: the section itself
// where the surface faces down, and the silhouette seen from below (where the vertex normals' z,
// interpolated over the face, is 0) where the surface lies below the paper.  It holds the plane
// section footprint_loops gives, and reaches past it where a section's widest points lie below
// the paper (a flattened belly, a tip dragged along it).  Loops of two parts of the surface may
// overlap; their union (positive fill) is the region.  Empty when nothing is below the paper.
std::vector<Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>> footprint_projection(
    const SurfaceMesh& mesh);
// ... with the vertex normals' z given, one a vertex (a sweep blends its two ends' normals with
// the vertices rather than summing them again at each blend)
std::vector<Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>> footprint_projection(
    const SurfaceMesh& mesh, const std::vector<double>& normal_z);
// the vertex normals' z (area-weighted over every face, normalised)
std::vector<double> vertex_normal_z(const SurfaceMesh& mesh);

// Sum of the signed (shoelace) areas of the loops, mm^2.
double loops_area(
    const std::vector<Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>>& loops);

// What the glyph driver reads of a footprint each frame, seen along a heading (rad):
// the area centroid (mm), the extent across the heading (mm), and how far the loops reach
// behind and ahead of the centroid along it (mm).  A centroid outside the points' bounds (a
// sliver whose outer loop and hole nearly cancel) is replaced by the points' mean.
// `valid` is false when there is no footprint (no loops, or |area| < 1e-9 mm^2).
struct FootprintSpan {
  bool valid = false;
  Vec2 centroid = Vec2::Zero();
  double width = 0.0, behind = 0.0, ahead = 0.0;
};
FootprintSpan footprint_span(
    const std::vector<Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>>& loops, double heading);

}  // namespace brushwork
