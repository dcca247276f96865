/**
 * @class   vtkRBFVolumeMapper
 * @brief   Volume renders the points of a point set as a Gaussian RBF field.
 *
 * Every point i of the input vtkPointSet (polydata, unstructured grid, ...; cells are
 * ignored) adds the Gaussian
 *   phi_i(x) = Kappa * k_i * exp(-|x - x_i|^2 / (2 r_i^2)),  truncated at Sigma * r_i,
 * to a scalar field that is ray cast with the vtkVolumeProperty of the vtkVolume: its
 * colour and scalar opacity functions (opacity per ScalarOpacityUnitDistance, corrected for
 * the step), and, when its Shade flag is on, Lambert + Phong lighting with the renderer's
 * lights and the field's analytic gradient (Knoll et al., "RBF Volume Ray Casting on
 * Multicore and Manycore CPUs", EuroVis 2014).
 *   k_i: the first component of ValueArrayName, or 1 when it is not set.
 *   r_i: ScaleFactor * (the first component of ScaleArray, or Radius when not set); Radius 0
 *        (the default) is automatic: the typical particle spacing s (the median distance to
 *        the nearest neighbour, on a sample: vtkRayMapperParticleSizes). With r = s the
 *        field of a lattice of particles ripples by exp(-2 pi^2) ~ 3e-9 of its mean: smooth,
 *        yet a feature one spacing wide still shows; a radius from the bounds would blur a
 *        dense set and break a sparse one into beads, and would change with the units.
 *
 * Multi-field classification (section 5.5): with FieldArrayName set, the distinct values
 * of that point array (a category, such as an atom type) split the particles into up to
 * four fields, in increasing order of value; field m is classified with component m of the
 * volume property (its own colour and opacity functions), and the fields are blended per
 * sample.
 *
 * The rays go in square packets that walk a BVH (Embree's builder) once per pass of
 * SamplesPerPass samples, filling a per-packet sample buffer; a packet stops when all its
 * rays reach TerminationOpacity. Method DIRECT gathers the particles at every sample
 * instead (the reference method, much slower). Changing Kappa, Sigma, SampleDistance, the
 * transfer functions or the lights never rebuilds the BVH. Opaque geometry already drawn
 * stops the rays; the depth buffer is read only when the renderer holds some (effect
 * opaque_depth).
 *
 * Bad input never poisons the image: points with NaN/Inf coordinates or values (or values
 * beyond float), and radii that are NaN, infinite, zero, negative or above 1e15, are skipped
 * with one warning saying how many.
 * Numeric properties reject NaN and infinity and clamp out-of-range values, each with one
 * warning (vtkRayMapperSetGet.h; lengths up to 1e15); an array of several components read
 * as a scalar gives its first component (one warning when they differ); a degenerate camera
 * (the eye at the focal point, a NaN position) gives one warning and nothing drawn.
 *
 * GetStatistics() reports phase times, counters and effects of the last render.
 */
#ifndef vtkRBFVolumeMapper_h
#define vtkRBFVolumeMapper_h

#include "RayMappersMappersModule.h" // for export macro
#include "vtkRayMapperParticleVolumeMapper.h"
#include "vtkRayMapperSetGet.h" // for vtkRayMapperSetClampMacro

#include <memory> // for std::unique_ptr

class vtkPointSet;
struct vtkRayMapperView;
namespace raymappers
{
class RenderStatistics;
struct RBFRenderParameters;
}

#define VTK_RBF_METHOD_COHERENT 0
#define VTK_RBF_METHOD_DIRECT 1

class RAYMAPPERSMAPPERS_EXPORT vtkRBFVolumeMapper : public vtkRayMapperParticleVolumeMapper
{
public:
  static vtkRBFVolumeMapper* New();
  vtkTypeMacro(vtkRBFVolumeMapper, vtkRayMapperParticleVolumeMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Global scale of the kernels (the paper's kappa). Default 0: automatic, 1 / the median
   * over 256 particles of the sum of the unit Gaussians at a particle (ParticleBVH.h's
   * medianWeightSum), so that where the particles are as dense as usual the field of
   * particles with the value k is about k: the volume property's transfer functions over
   * the value array's range (ParaView's ColorBy) then classify the values, not the density
   * (with kappa 1 the field of overlapping Gaussians is about 16 k and saturates them).
   */
  vtkRayMapperSetClampMacro(Kappa, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(Kappa, double);
  ///@}

  ///@{
  /** The kappa in use, Kappa or the automatic one, and the number of particles drawn, for
   * the current input (the particles and the BVH are built for it when needed, as the next
   * render would). */
  double GetKappaInUse();
  vtkIdType GetNumberOfParticlesInUse();
  ///@}

  ///@{
  /**
   * Truncation of each Gaussian at Sigma radii (the paper's sigma). Default 3, the knee of
   * the measured error-versus-time curve: the cut leaves exp(-sigma^2 / 2) of the peak at the
   * support's edge (13.5% at 2, 1.1% at 3, 0.03% at 4), and on 2LYZ seen from far at 512 x
   * 512 (raymappers-bench rbf, against a converged image) sigma 2 -> 3 costs 1.21x the time
   * for 5.9x less rmse (0.0077 -> 0.0013) while 3 -> 4 costs 1.72x for 1.3x less; on the
   * LAMMPS crack seen from far 2 -> 3 costs 1.47x for 19x less (0.047 -> 0.0025), 3 -> 4
   * 1.18x for 1.8x less. Open VKL's particle volume cuts at 3 radii too.
   */
  vtkRayMapperSetClampMacro(Sigma, double, 0.0, 1000.0);
  vtkGetMacro(Sigma, double);
  ///@}

  ///@{
  /**
   * Distance between samples along a ray (model units); 0 (default) chooses half the mean
   * radius.
   */
  vtkRayMapperSetClampMacro(SampleDistance, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(SampleDistance, double);
  ///@}

  ///@{
  /**
   * Constant radius (used without a radius array), a radius array ScaleArray (first
   * component) and a factor ScaleFactor on either (vtkPointGaussianMapper's names).
   * Defaults 0 (automatic: GetAutomaticRadiusPerSpacing() = 1 times the typical spacing of
   * the points; 1% of the bounds' diagonal without one), none, 1.
   */
  vtkRayMapperSetClampMacro(Radius, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(Radius, double);
  static double GetAutomaticRadiusPerSpacing()
  {
    return vtkRayMapperParticleSizes::RBFRadiusPerSpacing;
  }
  ///@}

  /** The constant radius in use for the current input: Radius, or the automatic one when
   * Radius is 0 (before ScaleFactor). */
  double GetRadiusInUse();

  ///@{
  /** @deprecated RadiusArrayName and RadiusScale (vtkRayMapperDeprecatedRadiusNamesMacro). */
  vtkRayMapperDeprecatedRadiusNamesMacro();
  ///@}

  ///@{
  /**
   * Point array of the particles' values k_i (first component); none (default): 1.
   */
  vtkSetStringMacro(ValueArrayName);
  vtkGetStringMacro(ValueArrayName);
  ///@}

  ///@{
  /**
   * Categorical point array splitting the particles into fields (up to 4); none (default):
   * one field.
   */
  vtkSetStringMacro(FieldArrayName);
  vtkGetStringMacro(FieldArrayName);
  ///@}

  ///@{
  /**
   * Classify the weighted average of the heights instead of their sum (the name of
   * vtkGeneralizedKernel's option): field m's value is Phi_m / W_m, W_m(x) = Kappa
   * sum_i exp(-|x - x_i|^2 / (2 r_i^2)) over its particles (the same truncated Gaussians
   * with height 1), and the opacity of a unit distance holds for the coverage
   * min(1, W_m) of it (a step's opacity a becomes 1 - (1 - a)^min(1, W_m)); shading uses
   * the gradient of sum_m W_m. The colour map then reads the values' own range (a signed
   * pressure, a velocity) at any particle density, and where no particle reaches nothing
   * is drawn even when the map is opaque at 0; with the paper's sum (off, the default)
   * the value is the density times the height, the right field for a density or heights
   * of 1, and a map opaque at 0 fills the particles' whole bounds. Costs one more buffer
   * row per field and sample.
   */
  vtkSetMacro(NormalizeWeights, bool);
  vtkGetMacro(NormalizeWeights, bool);
  vtkBooleanMacro(NormalizeWeights, bool);
  ///@}

  ///@{
  /**
   * A ray stops once its opacity reaches this (1: never early). Default 0.99.
   */
  vtkRayMapperSetClampMacro(TerminationOpacity, double, 0.0, 1.0);
  vtkGetMacro(TerminationOpacity, double);
  ///@}

  ///@{
  /**
   * Samples per ray and pass of the packet's buffer (the paper's K, 1 to 256; default 32),
   * rays per packet side (1 to 8; default 8: 64 rays), particles per BVH leaf (1 to 64;
   * default 8; changing it rebuilds the BVH) and screen tile size (default 32).
   */
  vtkRayMapperSetClampMacro(SamplesPerPass, int, 1, 256);
  vtkGetMacro(SamplesPerPass, int);
  vtkRayMapperSetClampMacro(PacketSize, int, 1, 8);
  vtkGetMacro(PacketSize, int);
  vtkRayMapperSetClampMacro(LeafSize, int, 1, 64);
  vtkGetMacro(LeafSize, int);
  vtkRayMapperSetClampMacro(TileSize, int, 4, 1024);
  vtkGetMacro(TileSize, int);
  ///@}

  ///@{
  /**
   * VTK_RBF_METHOD_COHERENT (default: packets and sample buffer) or VTK_RBF_METHOD_DIRECT
   * (per-sample gathering, the reference).
   */
  vtkRayMapperSetClampMacro(Method, int, VTK_RBF_METHOD_COHERENT, VTK_RBF_METHOD_DIRECT);
  vtkGetMacro(Method, int);
  ///@}

  ///@{
  /**
   * The box the samples are restricted to (xmin, xmax, ymin, ymax, zmin, zmax in model
   * coordinates; default: all of space). Distributed rendering sets it to the process's
   * region of the partition (its particles plus the ghosts whose support reaches in), so
   * that the regions' images composite front to back to the one-process image.
   */
  vtkSetVector6Macro(RegionBounds, double);
  vtkGetVector6Macro(RegionBounds, double);
  ///@}

protected:
  vtkRBFVolumeMapper();
  ~vtkRBFVolumeMapper() override;

  /// The largest support of a particle (the bounds' growth).
  double GetSupportRadius(vtkPointSet* input) override;
  /// One render, in the mapper's task arena (Render runs it there).
  void RenderVolume(vtkRenderer* ren, vtkVolume* vol, vtkPointSet* input) override;
  void ReleaseBuilds() override;

  double Kappa = 0.0;
  double Sigma = 3.0;
  double SampleDistance = 0.0;
  double Radius = 0.0;
  char* ValueArrayName = nullptr;
  char* FieldArrayName = nullptr;
  double TerminationOpacity = 0.99;
  int SamplesPerPass = 32;
  int PacketSize = 8;
  int LeafSize = 8;
  int TileSize = 32;
  int Method = VTK_RBF_METHOD_COHERENT;
  bool NormalizeWeights = false;
  double RegionBounds[6] = { -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX,
    -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX };

private:
  vtkRBFVolumeMapper(const vtkRBFVolumeMapper&) = delete;
  void operator=(const vtkRBFVolumeMapper&) = delete;

  /// Rebuilds the particles (and marks the BVH stale) when the input or the arrays changed.
  bool UpdateParticles(vtkPointSet* input);
  /// The particles, then the BVH over them, rebuilt where their stamps changed.
  void UpdateAcceleration(vtkPointSet* input, raymappers::RenderStatistics& stats);
  /// UpdateAcceleration for the mapper's input outside a render (statistics discarded).
  void UpdateForCurrentInput();
  /// Kappa, or the automatic kappa of the particles and BVH as built.
  double KappaForBuiltParticles();
  /// The kernel's parameters: the properties, the model transform, lights and material.
  raymappers::RBFRenderParameters GatherParameters(vtkRenderer* ren,
    vtkVolume* vol,
    const vtkRayMapperView& view);

  struct Internals;
  std::unique_ptr<Internals> Impl;
};

#endif
