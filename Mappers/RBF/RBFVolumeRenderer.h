// Volume ray casting of an RBF particle field (Knoll et al. 2014). Each pixel's ray takes
// samples at t_k = k dt (k integer, t from the ray's start on the near plane) inside the
// particles' enlarged bounds and in front of opaque geometry, classifies each field's
// value Phi_m(x) with that field's transfer function and blends front to back
// (section 3.2, Listing 1; opacities corrected for dt from the unit distance).
//
// Coherent method (section 4): rays go in square packets; the samples of a packet are
// taken in passes of K samples per ray (section 4.2). In a pass the packet walks the BVH
// once, nodes grown by sigma r_max, and every particle of a leaf adds its Gaussian to each
// buffered sample of each ray within its support (section 4.1, steps 4-5). The packet's
// rays sit in SIMD lanes (section 5.3): a node's slabs and a particle's support are tested
// against all of them at once. With u = t + b (b = f.d, f = o - x_i) and h^2 the squared
// distance from x_i to the ray's line,
//   g(t) = kappa k_i exp(-(u^2 + h^2) / 2r^2)   for t = k dt in [-b - w, -b + w],
//   w = sqrt(sigma^2 r^2 - h^2),
// evaluated one sample at a time for a SIMD block of 16 rays (the buffer holds a sample's
// values of the packet's rays side by side) with a polynomial exp (FastExp.h), over the
// block's samples in the support. The buffer is then integrated, and the packet stops
// when every ray's opacity reaches the termination threshold. Gradients (equation 4, for
// the Gaussian above grad phi = -phi (x - x_i)/r^2) are accumulated only when shading is
// on.
//
// Normalized weights (an option beside the paper's field, for values that are an
// attribute rather than a density): the value classified is the weighted average of the
// heights, Phi_m / W_m with W_m(x) = kappa sum_i exp(-|x - x_i|^2 / 2r_i^2) over field m's
// particles (the same truncated Gaussians with unit heights), and the opacity of a unit
// distance holds for the coverage c_m = min(1, W_m): a step's opacity alpha becomes
// 1 - (1 - alpha)^c_m, the extinction scaled by c_m. Where no particle reaches (W_m = 0)
// nothing is drawn, whatever the transfer function gives 0; where the particles are as
// dense as usual (W_m >= 1 with the automatic kappa) the value's own opacity holds; the
// shading normal is the gradient of W_m summed over the fields (the particles' density
// surface) instead of that of Phi.
//
// Direct method (section 3.3, the reference): every sample gathers the particles whose
// support holds it through the same BVH, one point query per sample.
#ifndef RayMappers_RBFVolumeRenderer_h
#define RayMappers_RBFVolumeRenderer_h

#include "Mappers/Common/Frame.h"
#include "Mappers/Common/Lighting.h"
#include "Mappers/RBF/ParticleBVH.h"
#include "Mappers/RBF/RBFParticles.h"
#include "Mappers/Common/RayCamera.h"
#include "Mappers/Common/RegionBox.h"
#include "Mappers/Common/RenderStatistics.h"
#include "Mappers/Common/TransferFunctionTable.h"
#include "Mappers/Common/View.h"

#include <vector>

namespace raymappers
{

constexpr int MaxRBFPacketSide = 8;
constexpr int MaxRBFSamplesPerPass = 256;

struct RBFRenderParameters
{
  double kappa = 1.0;          // global scale of the kernels
  double sigma = 2.0;          // support: sigma r_i
  double sampleDistance = 0.1; // dt (model units), > 0
  double terminationOpacity = 0.99;
  int samplesPerPass = 32; // K
  int packetSide = 8;      // packets of side x side rays
  int tileSize = 32;
  bool direct = false; // the direct (gathering) method instead of the coherent one
  // Classify Phi_m / W_m with the opacity scaled by the coverage min(1, W_m) (see above)
  // instead of Phi_m.
  bool normalizeWeights = false;
  // Shading with the gradient (off: emission and absorption only).
  bool shade = false;
  std::vector<Light> lights; // world space
  Material material;
  double modelToWorld[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
  double normalToWorld[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
  // Samples only inside this box (model coordinates; distributed rendering, RegionBox.h).
  RegionBox region;
};

/// What the RBF renderer draws: the particles, their BVH, and the classification of their
/// fields (`fields[m]` classifies field m; missing fields use the last table).
struct RBFScene
{
  const RBFParticles& particles;
  const ParticleBVH& bvh;
  const std::vector<TransferFunctionTable>& fields;
};

/// Renders the particles seen by the view's camera into `frame` (premultiplied RGBA, every
/// pixel written; its depth is left as it is: a volume writes no depth). Rays stop at the
/// view's opaque depth.
/// Counters: rays, packets, culled_packets (packets whose frustum misses the data: no ray set
/// up), staggered_blocks (SIMD blocks of rays integrated each from its own first sample),
/// passes, samples, node_visits, deposits, terminated_rays.
/// Effects: shading, multi_field, early_termination, empty_space_skipping,
/// normalized_weights.
void renderRBF(const RBFScene& scene,
  const View& view,
  const RBFRenderParameters& params,
  Frame& frame,
  RenderStatistics& stats);

} // namespace raymappers

#endif
