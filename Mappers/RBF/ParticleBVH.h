// Bounding volume hierarchy over RBF particles (Knoll et al. 2014, section 5.1), built with
// Embree's rtcBuildBVH (SAH, binary nodes, nodes of at most `leafSize` particles become
// leaves) from the
// boxes x_i +- r_i, then flattened into one array in depth-first order and the particles
// permuted into leaf order, so a leaf owns a contiguous range.
//
// A node stores the box of its particles' centres and the largest radius below it. At
// traversal the box is grown by sigma r_max (section 5.3: "dynamically expanding extents of
// every BVH node by sigma"): it then holds every particle's support, for any sigma, so
// changing sigma or kappa never rebuilds.
#ifndef RayMappers_ParticleBVH_h
#define RayMappers_ParticleBVH_h

#include "Mappers/RBF/RBFParticles.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace raymappers
{

struct BVHNode
{
  float lo[3]; // box of the centres below
  float rMax;  // largest radius below
  float hi[3];
  // Inner node (count 0): children `first` and `first + 1`. Leaf (count > 0): particles
  // [first, first + count).
  std::uint32_t first;
  std::uint32_t count;
};

class ParticleBVH
{
public:
  /// Builds over `particles`, permuting them into leaf order (they must stay unchanged
  /// until the next build). leafSize is clamped to [1, 64].
  void build(RBFParticles& particles, int leafSize);

  bool empty() const { return Nodes.empty(); }
  const std::vector<BVHNode>& nodes() const { return Nodes; }
  int depth() const { return Depth; }
  std::size_t memoryBytes() const { return Nodes.size() * sizeof(BVHNode); }

private:
  std::vector<BVHNode> Nodes;
  int Depth = 0;
};

/// Depth-first traversal: calls leaf(p) for every particle p of the leaves below the nodes
/// that meets(node) accepts (a rejected node's subtree is skipped); returns the nodes
/// visited. `stack` is scratch space, reused between calls.
template <typename Meets, typename Leaf>
std::size_t traverseBVH(const std::vector<BVHNode>& nodes,
  std::vector<std::uint32_t>& stack,
  Meets meets,
  Leaf leaf)
{
  std::size_t visits = 0;
  stack.assign(1, 0u);
  while (!stack.empty())
  {
    const BVHNode& node = nodes[stack.back()];
    stack.pop_back();
    ++visits;
    if (!meets(node))
    {
      continue;
    }
    if (node.count == 0)
    {
      stack.push_back(node.first + 1);
      stack.push_back(node.first);
      continue;
    }
    for (std::uint32_t p = node.first; p < node.first + node.count; ++p)
    {
      leaf(p);
    }
  }
  return visits;
}

/// Whether x lies in the node's box grown by g on every side (a point query's test).
inline bool grownBoxHolds(const BVHNode& node, const Vec3f& x, float g)
{
  return !(x.x < node.lo[0] - g || x.x > node.hi[0] + g || x.y < node.lo[1] - g ||
    x.y > node.hi[1] + g || x.z < node.lo[2] - g || x.z > node.hi[2] + g);
}

/// The automatic kappa's measure of density: the median, over up to `sampleSize` particles
/// (evenly strided), of the sum of the unit Gaussians at the particle's centre,
///   W(x_i) = sum_j exp(-|x_i - x_j|^2 / (2 r_j^2)) over |x_i - x_j| <= sigma r_j
/// (i included, so W >= 1; a point query of the BVH with its nodes grown by sigma r_max).
/// On a cubic lattice of spacing s with r = s it is (sum_n exp(-n^2 / 2))^3 = 15.7.
/// 0 when there are no particles.
double medianWeightSum(const RBFParticles& particles,
  const ParticleBVH& bvh,
  float sigma,
  std::size_t sampleSize = 256);

} // namespace raymappers

#endif
