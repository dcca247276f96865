#include "Mappers/RBF/ParticleBVH.h"
#include "Mappers/Common/EmbreeDevice.h"
#include "Mappers/Common/PermuteInPlace.h"

#include <embree3/rtcore.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

namespace raymappers
{

namespace
{
// Embree's builder hands out nodes through these callbacks; they live in its thread-local
// allocator until the flattening below copies them.
struct TempNode
{
  bool leaf;
  std::uint32_t count;      // leaf: particles
  TempNode* child[2];       // inner
  const std::uint32_t* ids; // leaf: the particles' indices (in the allocator too)
};

void* createNode(RTCThreadLocalAllocator alloc, unsigned int, void*)
{
  auto* node = static_cast<TempNode*>(rtcThreadLocalAlloc(alloc, sizeof(TempNode), 16));
  node->leaf = false;
  node->count = 0;
  node->child[0] = node->child[1] = nullptr;
  node->ids = nullptr;
  return node;
}

void setNodeChildren(void* nodePtr, void** children, unsigned int childCount, void*)
{
  auto* node = static_cast<TempNode*>(nodePtr);
  for (unsigned int c = 0; c < childCount && c < 2; ++c)
  {
    node->child[c] = static_cast<TempNode*>(children[c]);
  }
}

void setNodeBounds(void*, const RTCBounds**, unsigned int, void*)
{
  // The flattened nodes get the bounds of their centres, computed from the particles.
}

void* createLeaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t count, void*)
{
  auto* node = static_cast<TempNode*>(rtcThreadLocalAlloc(alloc, sizeof(TempNode), 16));
  auto* ids =
    static_cast<std::uint32_t*>(rtcThreadLocalAlloc(alloc, count * sizeof(std::uint32_t), 4));
  for (size_t i = 0; i < count; ++i)
  {
    ids[i] = prims[i].primID;
  }
  node->leaf = true;
  node->count = static_cast<std::uint32_t>(count);
  node->child[0] = node->child[1] = nullptr;
  node->ids = ids;
  return node;
}

// The build's Embree device and BVH (whose allocator holds the TempNodes), released in that
// order, also when the build throws.
struct EmbreeBuild
{
  RTCDevice device = nullptr;
  RTCBVH bvh = nullptr;
  void release()
  {
    if (bvh)
    {
      rtcReleaseBVH(bvh);
      bvh = nullptr;
    }
  }
  ~EmbreeBuild()
  {
    release();
    if (device)
    {
      rtcReleaseDevice(device);
    }
  }
};

// The primitives of the build (section 5.1): each particle's box x_i +- r_i.
LargeBuffer<RTCBuildPrimitive> particleBoxes(const RBFParticles& particles)
{
  const std::size_t n = particles.size();
  LargeBuffer<RTCBuildPrimitive> prims(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 16384),
    [&](const tbb::blocked_range<std::size_t>& range)
    {
      for (std::size_t i = range.begin(); i != range.end(); ++i)
      {
        const Vec3f& c = particles.centers[i];
        const float r = particles.radii[i];
        RTCBuildPrimitive& p = prims[i];
        p.lower_x = c.x - r;
        p.lower_y = c.y - r;
        p.lower_z = c.z - r;
        p.upper_x = c.x + r;
        p.upper_y = c.y + r;
        p.upper_z = c.z + r;
        p.geomID = 0;
        p.primID = static_cast<unsigned int>(i);
      }
    });
  return prims;
}

// Embree's SAH build over the boxes: binary nodes, a node of at most leafSize particles is a
// leaf. The nodes live in `bvh` until it is released.
const TempNode* buildSAH(RTCDevice device,
  RTCBVH bvh,
  LargeBuffer<RTCBuildPrimitive>& prims,
  int leafSize)
{
  RTCBuildArguments args = rtcDefaultBuildArguments();
  args.buildQuality = RTC_BUILD_QUALITY_MEDIUM;
  args.maxBranchingFactor = 2;
  args.maxDepth = 48;
  args.minLeafSize = static_cast<unsigned int>(leafSize); // (a smaller node is a leaf)
  args.maxLeafSize = static_cast<unsigned int>(leafSize);
  args.bvh = bvh;
  args.primitives = prims.data();
  args.primitiveCount = prims.size();
  args.primitiveArrayCapacity = prims.size();
  args.createNode = createNode;
  args.setNodeChildren = setNodeChildren;
  args.setNodeBounds = setNodeBounds;
  args.createLeaf = createLeaf;
  const auto* root = static_cast<TempNode*>(rtcBuildBVH(&args));
  if (!root)
  {
    ThrowOnEmbreeError(device, "rtcBuildBVH");
    throw std::runtime_error("Embree: rtcBuildBVH failed");
  }
  return root;
}

// Flattens the tree depth first into `nodes` (children a, a + 1 after their parent); the
// leaves take their particles in order, which gives the permutation returned (new index to
// input index). `depth` becomes the tree's depth.
std::vector<std::uint32_t> flatten(const TempNode* root,
  std::size_t n,
  int leafSize,
  std::vector<BVHNode>& nodes,
  int& depth)
{
  std::vector<std::uint32_t> order;
  order.reserve(n);
  nodes.reserve(2 * n / static_cast<std::size_t>(leafSize) + 2);
  struct Item
  {
    const TempNode* node;
    std::uint32_t index;
    int depth;
  };
  std::vector<Item> stack{ { root, 0, 1 } };
  nodes.emplace_back();
  while (!stack.empty())
  {
    const Item item = stack.back();
    stack.pop_back();
    depth = std::max(depth, item.depth);
    BVHNode& out = nodes[item.index];
    if (item.node->leaf)
    {
      out.first = static_cast<std::uint32_t>(order.size());
      out.count = item.node->count;
      order.insert(order.end(), item.node->ids, item.node->ids + item.node->count);
      continue;
    }
    const auto a = static_cast<std::uint32_t>(nodes.size());
    nodes.emplace_back();
    nodes.emplace_back();
    BVHNode& parent = nodes[item.index]; // (emplace_back may have moved it)
    parent.first = a;
    parent.count = 0;
    stack.push_back({ item.node->child[1], a + 1, item.depth + 1 });
    stack.push_back({ item.node->child[0], a, item.depth + 1 });
  }
  return order;
}

// Permutes the particles into leaf order, an array at a time (the peak holds one array
// twice, not the whole set).
void permute(RBFParticles& particles, const std::vector<std::uint32_t>& order)
{
  PermuteScratch scratch;
  permuteInPlace(particles.centers, order.data(), scratch);
  permuteInPlace(particles.radii, order.data(), scratch);
  permuteInPlace(particles.values, order.data(), scratch);
  permuteInPlace(particles.fields, order.data(), scratch);
}

// Each node's box of the centres below it and their largest radius, bottom-up: children
// always come after their parent, so a reverse sweep sees both children of a node before
// the node.
void computeBounds(std::vector<BVHNode>& nodes, const RBFParticles& particles)
{
  for (std::size_t k = nodes.size(); k-- > 0;)
  {
    BVHNode& node = nodes[k];
    const float big = std::numeric_limits<float>::max();
    float lo[3] = { big, big, big }, hi[3] = { -big, -big, -big }, rMax = 0.f;
    if (node.count > 0)
    {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
      {
        const Vec3f& c = particles.centers[i];
        for (int a = 0; a < 3; ++a)
        {
          lo[a] = std::min(lo[a], c[a]);
          hi[a] = std::max(hi[a], c[a]);
        }
        rMax = std::max(rMax, particles.radii[i]);
      }
    }
    else
    {
      for (const std::uint32_t c : { node.first, node.first + 1 })
      {
        for (int a = 0; a < 3; ++a)
        {
          lo[a] = std::min(lo[a], nodes[c].lo[a]);
          hi[a] = std::max(hi[a], nodes[c].hi[a]);
        }
        rMax = std::max(rMax, nodes[c].rMax);
      }
    }
    std::copy(lo, lo + 3, node.lo);
    std::copy(hi, hi + 3, node.hi);
    node.rMax = rMax;
  }
}
}

void ParticleBVH::build(RBFParticles& particles, int leafSize)
{
  Nodes.clear();
  Depth = 0;
  const std::size_t n = particles.size();
  if (n == 0)
  {
    return;
  }
  leafSize = std::clamp(leafSize, 1, 64);
  EmbreeBuild embree;
  embree.device = NewEmbreeDevice(nullptr);
  LargeBuffer<RTCBuildPrimitive> prims = particleBoxes(particles);
  embree.bvh = rtcNewBVH(embree.device);
  const TempNode* root = buildSAH(embree.device, embree.bvh, prims, leafSize);
  prims = LargeBuffer<RTCBuildPrimitive>(); // freed: the leaves hold copies of their ids
  const std::vector<std::uint32_t> order = flatten(root, n, leafSize, Nodes, Depth);
  embree.release();
  permute(particles, order);
  computeBounds(Nodes, particles);
}

namespace
{
/// W(x) of medianWeightSum: the point query of x in the BVH grown by sigma r_max.
double weightSumAt(const RBFParticles& particles,
  const std::vector<BVHNode>& nodes,
  const Vec3f& x,
  float sigma,
  std::vector<std::uint32_t>& stack)
{
  double sum = 0.0;
  traverseBVH(
    nodes, stack, [&](const BVHNode& node) { return grownBoxHolds(node, x, sigma * node.rMax); },
    [&](std::uint32_t p)
    {
      const Vec3f e = x - particles.centers[p];
      const float d2 = dot(e, e), r = particles.radii[p];
      if (d2 <= sigma * sigma * r * r)
      {
        sum += std::exp(-d2 / (2.f * r * r));
      }
    });
  return sum;
}
}

double medianWeightSum(const RBFParticles& particles,
  const ParticleBVH& bvh,
  float sigma,
  std::size_t sampleSize)
{
  const std::size_t n = particles.size();
  const std::size_t m = std::min(n, sampleSize);
  if (m == 0 || bvh.empty())
  {
    return 0.0;
  }
  std::vector<double> sums(m);
  std::vector<std::uint32_t> stack;
  for (std::size_t k = 0; k < m; ++k)
  {
    const std::size_t i = (2 * k + 1) * n / (2 * m);
    sums[k] = weightSumAt(particles, bvh.nodes(), particles.centers[i], sigma, stack);
  }
  std::nth_element(sums.begin(), sums.begin() + static_cast<std::ptrdiff_t>(m / 2), sums.end());
  return sums[m / 2];
}

} // namespace raymappers
