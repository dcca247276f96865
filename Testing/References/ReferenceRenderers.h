// The reference pictures of the end-to-end tests (ReferenceScene.h), each from its
// definition, in double precision, every particle considered for every pixel:
// - spheres: the closed-form first hit of each pixel's ray over all spheres, Phong shaded;
// - RBF: the emission-absorption integral of the Gaussian field
//     phi(x) = kappa sum_i k_i exp(-|x - x_i|^2 / 2 r_i^2)      (Knoll et al. 2014, eq. 1)
//   untruncated (a Gaussian is dropped beyond `cutoff` radii, exp(-cutoff^2 / 2) of its peak:
//   1.5e-8 at the default 6), classified by the transfer function; or (average) the
//   weighted average phi / w, w(x) = kappa sum_i exp(-|x - x_i|^2 / 2 r_i^2), classified
//   with its extinction scaled by min(1, w);
// - SPH: the same integral of the normalized field A / B or of A (Limper 2012, eq. 3.14 and
//   3.15) with A = sum_i Q_i V_i W(|x - x_i|, H_i), B = sum_i V_i W(|x - x_i|, H_i), its own
//   kernel code, only where some support holds the point (B > 0);
// - the fluid's front surface: the first hit over the union of the particles' spheres.
// The volume integral along a ray, from the near plane to the far plane, takes the midpoint
// of every segment of length ds: a segment of extinction tau and colour c adds
// T (1 - exp(-tau ds)) c and multiplies the transmittance T by exp(-tau ds); ds is fixed and
// fine (the tests show that halving it changes nothing visible), with no early termination.
#ifndef RayMappers_Reference_ReferenceRenderers_h
#define RayMappers_Reference_ReferenceRenderers_h

#include "ReferenceScene.h"

namespace raymappers::reference
{

struct ReferenceSphere
{
  Point center;
  double radius = 1;
  Point color{ 1, 1, 1 };
  double opacity = 1; // renderTranslucentSpheres only
};

/// Straight colour with opacity 1 where a sphere is hit (the far root where the ray starts
/// inside one), and the hit's window depth.
ReferenceImage renderSpheres(const ReferenceCamera& camera,
  const std::vector<ReferenceSphere>& spheres,
  const std::vector<ReferenceLight>& lights,
  const ReferenceMaterial& material);

/// An unlit plane {x : normal . x = offset} (world) of straight colour and opacity, met
/// by the rays of renderTranslucentSpheres as one more layer (opacity 1: opaque geometry).
struct ReferencePlane
{
  Point normal;
  double offset = 0;
  Point color;
  double opacity = 1;
};

/// Translucent spheres, composited by definition: along each pixel's ray every layer in
/// [0, length] (each sphere once, at its first surface: the near root, or the far root where
/// the ray starts inside it; each plane where the ray crosses it) sorted by distance, then
///   C += (1 - A) a c,   A += (1 - A) a
/// front to back over all of them (no early termination), c the Phong colour of a sphere
/// (a plane's own colour). The depth is the first layer's.
ReferenceImage renderTranslucentSpheres(const ReferenceCamera& camera,
  const std::vector<ReferenceSphere>& spheres,
  const std::vector<ReferenceLight>& lights,
  const ReferenceMaterial& material,
  const std::vector<ReferencePlane>& planes);

/// Opacity 1 and the window depth of the first hit over the union of the spheres (colour
/// white): the front surface of a fluid of these particles.
ReferenceImage renderUnionSurface(const ReferenceCamera& camera,
  const std::vector<ReferenceSphere>& spheres);

struct ReferenceGaussian
{
  Point center;
  double radius = 1;
  double weight = 1; // k_i
};

struct RBFReference
{
  double kappa = 1;
  double cutoff = 6; // radii
  double step = 0;   // ds (world units), > 0
  bool average = false; // classify phi / w with the extinction times min(1, w)
};

ReferenceImage renderRBF(const ReferenceCamera& camera,
  const std::vector<ReferenceGaussian>& gaussians,
  const RBFReference& params,
  const ReferenceTransferFunction& tf);

enum class ReferenceKernel
{
  Poly6,
  CubicSpline,
  WendlandC2
};

/// W(r) of support H (W = 0 for r >= H), normalized in 3D (its integral over space is 1):
///   poly6:        315 / (64 pi H^3) (1 - q^2)^3,                q = r / H
///   cubic spline: 8 / (pi H^3) (1 - 6 q^2 + 6 q^3) for q <= 1/2,  16 / (pi H^3) (1 - q)^3
///   Wendland C2:  21 / (2 pi H^3) (1 - q)^4 (1 + 4 q)
double kernelWeight(ReferenceKernel kernel, double r, double H);

struct ReferenceSPHParticle
{
  Point center;
  double support = 1;  // H_i
  double quantity = 0; // Q_i
  double volume = 1;   // V_i
};

struct SPHReference
{
  ReferenceKernel kernel = ReferenceKernel::CubicSpline;
  bool normalized = true;
  double step = 0; // ds (world units), > 0
};

ReferenceImage renderSPH(const ReferenceCamera& camera,
  const std::vector<ReferenceSPHParticle>& particles,
  const SPHReference& params,
  const ReferenceTransferFunction& tf);

}

#endif
