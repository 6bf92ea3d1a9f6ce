#pragma once
// How far apart two triangle surfaces are: the symmetric maximum distance (Hausdorff),
// sampled as Metro does (Cignoni, Rocchini & Scopigno, "Metro: Measuring Error on
// Simplified Surfaces", 1998): points on every triangle of one surface, the distance of
// each to the nearest point of the other surface, the largest of them, both ways.
//
// Units: cm in, cm out. Both surfaces index one position array (a simplified mesh keeps
// original vertices, so this is how mesh_lod.h compares a level with its original, in the
// bind pose or any skinned pose). A triangle present in both (the same three indices in
// the same order) lies in the other surface: it is not sampled, and costs nothing.
//
// Sampling: a barycentric grid of n x n cells on each triangle (vertices, points along the
// edges, the centroid and the inside), n a multiple of 3 with cells no wider than
// `spacingCm`, at most kMaxSamplingSubdivisions. The distance to a surface is 1-Lipschitz,
// so the true maximum exceeds the sampled one by less than the cell width.

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace mlod {

inline constexpr int kMaxSamplingSubdivisions = 30;

// Squared distance (cm^2) from `point` to the triangle abc (its nearest point, by Voronoi
// regions: Ericson, "Real-Time Collision Detection", 5.1.5).
double pointTriangleDistanceSquared(const glm::dvec3& point, const glm::dvec3& a, const glm::dvec3& b,
                                    const glm::dvec3& c);

// An axis-aligned bounding-box tree over triangles, for nearest-point queries. Holds a copy
// of the triangles it needs (positions may go away after construction).
class TriangleTree {
public:
  TriangleTree(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices);
  ~TriangleTree();
  TriangleTree(TriangleTree&&) noexcept;
  TriangleTree& operator=(TriangleTree&&) noexcept;

  bool empty() const;
  // Squared distance (cm^2) from `point` to the nearest triangle; `limit` when none is
  // nearer than that (and for an empty tree), which lets a caller stop early. The nearest
  // triangle's number goes to *out_triangle (-1 when none), where given.
  double nearestSquared(const glm::dvec3& point, double limit, int* out_triangle = nullptr) const;
  // The point of triangle `triangle` (a number nearestSquared() gave) nearest to `point`.
  glm::dvec3 closestPoint(const glm::dvec3& point, int triangle) const;
  // Whether some triangle lies within sqrt(radiusSquared) of `point` (stops at the first).
  // *inout_hint, where given: a triangle number to try first (-1: none), replaced by the
  // one found; neighbouring points are usually answered by the same triangle.
  bool anyWithin(const glm::dvec3& point, double radiusSquared, int* inout_hint = nullptr) const;

private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

// Subdivisions of a triangle with this longest edge (cm) at this spacing (cm, > 0).
int samplingSubdivisions(double longestEdgeCm, double spacingCm);

// The largest distance (cm) from the sample points of the triangles of `from` (those not
// also in `to`) to the surface of `to`, or `floorCm` (>= 0) when none is farther: a caller
// that wants the maximum over many surfaces passes the largest so far, and every sample
// nearer than it is settled by the first triangle found within it, not the nearest one.
// Infinity when `to` is empty and `from` has something to sample.
double oneSidedMaxDistance(std::span<const glm::vec3> positions, std::span<const std::uint32_t> from,
                           std::span<const std::uint32_t> to, double spacingCm, double floorCm = 0.0);

// The same with the surface `to` given with its tree (TriangleTree(positions, to)), built
// once by a caller that measures many surfaces against it.
double oneSidedMaxDistance(std::span<const glm::vec3> positions, std::span<const std::uint32_t> from,
                           std::span<const std::uint32_t> to, const TriangleTree& toTree, double spacingCm,
                           double floorCm = 0.0);

// max(oneSidedMaxDistance(a -> b), oneSidedMaxDistance(b -> a), floorCm), cm.
double symmetricMaxDistance(std::span<const glm::vec3> positions, std::span<const std::uint32_t> a,
                            std::span<const std::uint32_t> b, double spacingCm, double floorCm = 0.0);

} // namespace mlod
