/**
 * @class   vtkSPHFluidMapper
 * @brief   Renders SPH particles as a homogeneous fluid (water): surfaces, absorption,
 *          refraction and ambient occlusion, from a view-adaptive voxelization.
 *
 * Every point i of the input vtkPointSet (cells are ignored) is a sphere of radius
 * r_i = ScaleFactor * (ScaleArray, else Radius); the union of the spheres is the fluid.
 * Radius 0 (the default) is automatic: the typical particle spacing s (the median distance
 * to the nearest neighbour, on a sample: vtkRayMapperParticleSizes). Spheres of radius s on a
 * cubic lattice leave no cavity (that needs r >= (sqrt(3)/2) s = 0.87 s) and bulge only
 * s - sqrt(s^2 - s^2/4) = 0.13 s between neighbours on a flat face.
 *
 * Lengths: with LengthUnit PARTICLE_RADIUS (the default) Density is the absorption per mean
 * particle radius rbar, and GapThreshold, SmoothingRadius, AmbientOcclusionRadius and
 * CellSize are in radii: the same particles in other units (x1e-3, x1e3) give the same
 * picture. LengthUnit WORLD takes them in the input's (model) units, as given.
 * Once per input, boundary-cell culling (BoundaryCulling, CellSize; sections 3.1 and 4.3)
 * finds the cells of a uniform grid that the spheres provably cover and drops the particles
 * of cells whose neighbours are all covered: the covered cells are filled as boxes instead,
 * with the same result. Each frame the mapper voxelizes the spheres into a perspective bit
 * grid at the render resolution with logarithmic depth layers (Zirr and Dachsbacher 2015,
 * section 4.2: the layers keep the angle AngleResolution, at most MaximumLayers of them), in
 * tiles that fit MemoryBudget, compresses each pixel's column into at most MaximumSpans
 * spans (the absorption beyond them stays exact), bridges gaps shorter than GapThreshold
 * (LengthUnit; 0: none), connects the spans of neighbouring pixels into surfaces, smooths
 * them with the radius SmoothingRadius (4 radii; 0: no smoothing pass; at most
 * SmoothingIterations iterations, 64), takes normals with a Sobel operator along the links and
 * renders (kernels: FluidCells.h, SpanVoxelizer.h, SurfaceLinks.h, FluidRenderer.h, which
 * give the formulas):
 *   - the front surface lit by the renderer's lights (all of its vtkLights: ParaView's
 *     light kit and headlight) with Color (or the scalars' colours, ScalarVisibility) and
 *     the vtkVolumeProperty's Ambient, Diffuse, Specular and SpecularPower: the diffuse part
 *     D and the specular highlight S;
 *   - Translucency on (default): Beer-Lambert absorption kappa = Density * AbsorptionColor
 *     per LengthUnit over all spans; the background shows through by T = exp(-kappa l), the
 *     highlight is reflected untinted and the body scatters omega D (1 - T) with the albedo
 *     omega_c = min_k kappa_k / kappa_c (a grey scattering coefficient min_k kappa_k):
 *     thin water is grey, deep water takes the colour it absorbs least (FluidRenderer.h);
 *   - RefractiveIndex != 1 (with Translucency): refraction, Fresnel reflection and total
 *     internal reflection by marching the rays through the columns, Bounces surface events;
 *   - AmbientOcclusion: deep screen-space occlusion over all layers, AmbientOcclusionSamples
 *     samples within AmbientOcclusionRadius.
 * Only the effects asked for run: no refraction march when the index is 1 or translucency
 * is off, no AO pass when it is off, no smoothing pass when the radius is 0 (statistics'
 * counters march_columns, ao_samples, filter_iterations stay 0), no colour lookup without
 * scalar colouring (color_samples).
 *
 * Why a vtkAbstractVolumeMapper (used with a vtkVolume): the picture depends on everything
 * opaque behind and around the fluid. VTK draws volumes after all opaque (and translucent)
 * geometry, so when Render runs the depth buffer holds every opaque surface: the mapper
 * reads it and ends each pixel's fluid at the geometry (VoxelizerParameters::stopDepth), so
 * translucent water absorbs only up to a wall inside it and refracted rays leave there. An
 * opaque fluid (Translucency off) is then drawn writing its front surface's depth under the
 * depth test (it hides and is hidden by geometry, and whatever is drawn after it respects
 * it); a translucent fluid is blended over what is drawn (premultiplied) without writing
 * depth, like any volume. A vtkPolyDataMapper would be drawn in the opaque pass, before
 * the rest of the opaque geometry it must see through.
 *
 * Bad input never poisons the image: particles with NaN/Inf coordinates and radii that are
 * NaN, infinite, zero, negative or above 1e15 are skipped with one warning saying how many;
 * a missing radius array falls back to Radius with a warning; an empty input draws nothing
 * with one warning.
 * Numeric properties reject NaN and infinity and clamp out-of-range values, each with one
 * warning (vtkRayMapperSetGet.h; lengths up to 1e15); an array of several components read
 * as a scalar gives its first component (one warning when they differ); a degenerate camera
 * (the eye at the focal point, a NaN position) gives one warning and nothing drawn.
 * The particles are rebuilt only when the input (a new time step) or the radius settings
 * change (counter particles_built); the voxelization is view-dependent and made every frame.
 *
 * GetStatistics() reports phase times (particles, cells, opaque_depth, splat, compress, connect,
 * filter, normals, ao, render or refract, draw), counters and effects of the last render.
 */
#ifndef vtkSPHFluidMapper_h
#define vtkSPHFluidMapper_h

#include "RayMappersMappersModule.h" // for export macro
#include "vtkRayMapperParticleVolumeMapper.h"
#include "vtkRayMapperSetGet.h" // for vtkRayMapperSetClampMacro

#include <memory> // for std::unique_ptr

class vtkPointSet;
class vtkScalarsToColors;
struct vtkRayMapperView;
namespace raymappers
{
class RenderStatistics;
struct FluidRenderParameters;
}

class RAYMAPPERSMAPPERS_EXPORT vtkSPHFluidMapper : public vtkRayMapperParticleVolumeMapper
{
public:
  static vtkSPHFluidMapper* New();
  vtkTypeMacro(vtkSPHFluidMapper, vtkRayMapperParticleVolumeMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** Constant particle radius (default 1), its point array ScaleArray, and a factor
   * ScaleFactor on either (1; vtkPointGaussianMapper's names). */
  vtkRayMapperSetClampMacro(Radius, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(Radius, double);
  static double GetAutomaticRadiusPerSpacing()
  {
    return vtkRayMapperParticleSizes::FluidRadiusPerSpacing;
  }
  ///@}

  /** The constant radius in use for the current input: Radius, or the automatic one when
   * Radius is 0 (before ScaleFactor). */
  double GetRadiusInUse();

  ///@{
  /** The unit of Density (absorption per unit), GapThreshold, SmoothingRadius,
   * AmbientOcclusionRadius and CellSize: the mean particle radius (PARTICLE_RADIUS, default)
   * or the input's own unit (WORLD). */
  vtkRayMapperLengthUnitMacro();
  ///@}

  ///@{
  /** @deprecated RadiusArrayName and RadiusScale (vtkRayMapperDeprecatedRadiusNamesMacro). */
  vtkRayMapperDeprecatedRadiusNamesMacro();
  ///@}

  ///@{
  /** Voxelization: angle resolution in degrees (14), at most this many depth layers
   * (16384), spans kept per pixel (7, at most 63), temporary memory in MB (0: automatic,
   * half the memory the process can still take when the frame starts, at least 512 MB; the
   * voxelizer takes only what its tiles need within it), gap threshold in LengthUnit (0: no
   * gap bridging). */
  vtkRayMapperSetClampMacro(AngleResolution, double, 0.01, 89.0);
  vtkGetMacro(AngleResolution, double);
  vtkRayMapperSetClampMacro(MaximumLayers, int, 1, 1 << 20);
  vtkGetMacro(MaximumLayers, int);
  vtkRayMapperSetClampMacro(MaximumSpans, int, 1, 63);
  vtkGetMacro(MaximumSpans, int);
  vtkRayMapperSetClampMacro(MemoryBudget, double, 0.0, 1.0e6);
  vtkGetMacro(MemoryBudget, double);
  vtkRayMapperSetClampMacro(GapThreshold, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(GapThreshold, double);
  ///@}

  ///@{
  /** Boundary-cell culling (on; Zirr 2015, 3.1 and 4.3): particles in full cells whose 26
   * neighbours are full are not splatted; the full cells are filled as boxes instead
   * (FluidCells.h: "full" means the cell's box is covered by the spheres, so the fluid is the
   * same). CellSize:
   * the culling grid's cell size in LengthUnit (0, default: twice the largest radius; at
   * least the largest radius). */
  vtkSetMacro(BoundaryCulling, bool);
  vtkGetMacro(BoundaryCulling, bool);
  vtkBooleanMacro(BoundaryCulling, bool);
  vtkRayMapperSetClampMacro(CellSize, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(CellSize, double);
  ///@}
  ///@{
  /**
   * Surface smoothing (Zirr 2015, section 4.6): radius in LengthUnit (4 particle radii by
   * default; 0: no smoothing pass) and the largest number of iterations (64).
   * The default is the knee of the curves measured by Testing/Benchmarks/
   * fluid_smoothing_curve.py at 640 x 480 (the radius about 10 pixels), against the union of
   * the spheres intersected in numpy. On PySPH's initial dam (a cubic lattice of 30 x 15 x 12
   * particles, radius = spacing), for R = 0, 0.5, 1, 1.5, 2, 3, 4, 6 radii (0 to 65
   * iterations): the RMS angle of the faces' normals to the box's (the lattice's bumps, on
   * the faces seen within 60 degrees of their normal; the union of spheres has 24) is 19.6,
   * 9.7, 5.4, 3.1, 1.75, 0.58, 0.20, 0.06 degrees; the largest distance of the smoothed front
   * surface to the spheres' 0.03, 0.17, 0.21, 0.27, 0.33, 0.39, 0.41, 0.43 radii. On the dam
   * break at t = 0.3 s (automatic radius 0.9 of the spacing) the rows of particles along the
   * side wall, seen obliquely, still show at R = 2 and are gone at R = 4 (looked at); there
   * the surface moves at most 0.32, 0.41, 0.42, 0.50 radii from the spheres' at R = 2, 3, 4,
   * 6 (99%: 0.18, 0.21, 0.23, 0.29), and along the rays 99% of the pixels move less than 0.62
   * radii at R = 4 (67 of 33,000 more than 1: thin sheets seen edge-on, where the ray grazes
   * the surface and a small move in space is a long one along the ray). R = 4 is where the
   * bumps are gone on faces seen obliquely too, at a distance from the spheres that has
   * stopped growing (0.41 -> 0.43 radii for 1.5 times the iterations); 43 iterations there,
   * about 34 ms at 640 x 480 on this machine's 2 cores, hence the cap of 64 (the paper's 20
   * stop R = 4 at 2 radii at this size). The filter's reach is R but its spread grows as the
   * square root of its iterations, so with more pixels per radius the same R smooths less,
   * and beyond the cap the reach shrinks (at 1280 x 960 the lattice keeps 2.0 degrees at
   * R = 4, its 86 iterations capped to 64: 3.5 degrees).
   */
  vtkRayMapperSetClampMacro(SmoothingRadius, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(SmoothingRadius, double);
  vtkRayMapperSetClampMacro(SmoothingIterations, int, 0, 1000);
  vtkGetMacro(SmoothingIterations, int);
  ///@}

  ///@{
  /** The solid colour of the fluid (0.55, 0.75, 0.95), used unless it is coloured by scalars. */
  vtkRayMapperSetVector3ClampMacro(Color, double, 0.0, 1.0);
  vtkGetVector3Macro(Color, double);
  ///@}

  ///@{
  /**
   * Colouring by scalars, as vtkMapper colours: with ScalarVisibility on (default off) and a
   * point array ColorArrayName, each particle's colour is its value mapped through the
   * LookupTable (its own range; without one, a vtkLookupTable over the array's range; alpha
   * ignored), and the fluid's surface colour at a point is the normalized SPH interpolation of
   * the particles' colours there (FluidColors.h: Wendland C2 of support 2 r_i, weights
   * V_i W), taken at the front surface and kept along the pixel's ray (the medium stays
   * homogeneous per pixel). Otherwise, or when the array is missing (one warning), Color.
   * The colours are rebuilt when the particles, the array, the table or these settings
   * change (counter colors_built); effect particle_colors, counter color_samples.
   */
  vtkSetMacro(ScalarVisibility, vtkTypeBool);
  vtkGetMacro(ScalarVisibility, vtkTypeBool);
  vtkBooleanMacro(ScalarVisibility, vtkTypeBool);
  vtkSetStringMacro(ColorArrayName);
  vtkGetStringMacro(ColorArrayName);
  void SetLookupTable(vtkScalarsToColors* lut);
  vtkScalarsToColors* GetLookupTable();
  ///@}

  /** The mapper's MTime, and the LookupTable's (as vtkMapper's). */
  vtkMTimeType GetMTime() override;

  ///@{
  /** Translucency (on): absorption per LengthUnit Density (0.5) * AbsorptionColor
   * (0.8, 0.35, 0.15): through 10 radii of fluid the blue light keeps exp(-0.75) = 47% and
   * the red 2%, through 40 radii 5% of the blue: a body a few particles thick still shows
   * (at 0.05 a 20-particle dam break was a faint veil) and what lies behind a thin one shows
   * through; off: an opaque surface that writes depth. */
  vtkSetMacro(Translucency, bool);
  vtkGetMacro(Translucency, bool);
  vtkBooleanMacro(Translucency, bool);
  vtkRayMapperSetVector3ClampMacro(AbsorptionColor, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetVector3Macro(AbsorptionColor, double);
  vtkRayMapperSetClampMacro(Density, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(Density, double);
  ///@}

  ///@{
  /** Index of refraction (1: no refraction march) and surface events per path (4). */
  vtkRayMapperSetClampMacro(RefractiveIndex, double, 0.1, 10.0);
  vtkGetMacro(RefractiveIndex, double);
  vtkRayMapperSetClampMacro(Bounces, int, 1, 64);
  vtkGetMacro(Bounces, int);
  ///@}

  ///@{
  /** Ambient occlusion (off), its radius in LengthUnit (4) and samples per pixel (16). */
  vtkSetMacro(AmbientOcclusion, bool);
  vtkGetMacro(AmbientOcclusion, bool);
  vtkBooleanMacro(AmbientOcclusion, bool);
  vtkRayMapperSetClampMacro(AmbientOcclusionRadius, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(AmbientOcclusionRadius, double);
  vtkRayMapperSetClampMacro(AmbientOcclusionSamples, int, 1, 1024);
  vtkGetMacro(AmbientOcclusionSamples, int);
  ///@}

  ///@{
  /**
   * Interactive rendering with the names of VTK's volume ray casters: the fluid voxelized
   * and rendered with rays ImageSampleDistance d pixels apart (the layers follow the coarser
   * pixels, so the grid shrinks by d^2 or more) and enlarged. AutoAdjustSampleDistances
   * (default on): interactive renders choose d from the last frame's time against
   * FrameBudget within [MinimumImageSampleDistance 1, MaximumImageSampleDistance 8]; still
   * renders give the full image. See vtkRayMapperSampleDistanceMacro (vtkRayMapperSetGet.h).
   */
  vtkRayMapperSampleDistanceMacro();
  ///@}

  ///@{
  /** @deprecated Subsampling p (0: AutoAdjustSampleDistances; 1 to 8: ImageSampleDistance p
   * with AutoAdjustSampleDistances off), kept for one release. */
  vtkRayMapperDeprecatedSubsamplingMacro(8);
  ///@}

protected:
  vtkSPHFluidMapper();
  ~vtkSPHFluidMapper() override;

  /// The largest support of a particle (the bounds' growth).
  double GetSupportRadius(vtkPointSet* input) override;
  /// One render, in the mapper's task arena (Render runs it there).
  void RenderVolume(vtkRenderer* ren, vtkVolume* vol, vtkPointSet* input) override;
  void ReleaseBuilds() override;

  double Radius = 0.0;
  int LengthUnit = PARTICLE_RADIUS;
  double AngleResolution = 14.0;
  int MaximumLayers = 16384;
  int MaximumSpans = 7;
  double MemoryBudget = 0.0;
  double GapThreshold = 0.0;
  bool BoundaryCulling = true;
  double CellSize = 0.0;
  double ImageSampleDistance = 1.0;
  vtkTypeBool AutoAdjustSampleDistances = 1;
  double MinimumImageSampleDistance = 1.0;
  double MaximumImageSampleDistance = 8.0;
  double FrameBudget = 0.0;
  double SmoothingRadius = 4.0;
  int SmoothingIterations = 64;
  double Color[3] = { 0.55, 0.75, 0.95 };
  vtkTypeBool ScalarVisibility = 0;
  char* ColorArrayName = nullptr;
  bool Translucency = true;
  double AbsorptionColor[3] = { 0.8, 0.35, 0.15 };
  double Density = 0.5;
  double RefractiveIndex = 1.0;
  int Bounces = 4;
  bool AmbientOcclusion = false;
  double AmbientOcclusionRadius = 4.0;
  int AmbientOcclusionSamples = 16;

private:
  vtkSPHFluidMapper(const vtkSPHFluidMapper&) = delete;
  void operator=(const vtkSPHFluidMapper&) = delete;

  /// Rebuilds the particles when the input, the radius array or the radius settings changed;
  /// returns whether it did.
  bool UpdateParticles(vtkPointSet* input);
  /// Rebuilds the particles' colours when the particles or the colouring changed; none
  /// (solid colour) without scalar colouring.
  void UpdateColors(vtkPointSet* input, raymappers::RenderStatistics& stats);
  /// Rebuilds the boundary-culling cells when the particles or the culling settings changed.
  void UpdateCells(raymappers::RenderStatistics& stats);
  /// The model-space length of LengthUnit: the particles' mean radius, or 1 for WORLD.
  double GetLengthUnitSize() const;
  /// The kernel's parameters: the properties, the model transform, lights and material.
  raymappers::FluidRenderParameters GatherParameters(vtkRenderer* ren,
    vtkVolume* vol,
    const vtkRayMapperView& view);
  /// The warning that the memory budget holds no voxel column, once per budget and size.
  void WarnAboutMemoryBudget(const vtkRayMapperView& view, const raymappers::RenderStatistics& stats);

  struct Internals;
  std::unique_ptr<Internals> Impl;
};

#endif
