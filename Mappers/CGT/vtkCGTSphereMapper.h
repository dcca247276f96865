/**
 * @class   vtkCGTSphereMapper
 * @brief   Renders every point of its input as an exact, ray-traced sphere.
 *
 * Each point of the input vtkPolyData (cells are ignored) becomes a sphere of radius
 *   r_i = ScaleFactor * (ScaleArray set ? radius[i] : Radius),
 * and Radius 0 (the default) is automatic: half the typical particle spacing s (the median
 * distance of a particle to its nearest neighbour, estimated on a sample of 1024:
 * vtkRayMapperParticleSizes), the radius at which spheres on a lattice touch. It follows the
 * data's units and density, not its bounds: a clustered halo and a sparse sample of the same
 * bounds get different radii, and the data scaled by 1e-3 or 1e3 the same picture.
 * Spheres are colored by the mapper's scalars through its lookup table (the usual
 * vtkMapper coloring: ScalarVisibility, ColorMode, SelectColorArray, ...) or by the
 * actor's color, and shaded with the renderer's lights (Lambert diffuse plus Phong
 * specular, from vtkProperty's Ambient/Diffuse/Specular/SpecularPower).
 *
 * The rays are traced on the CPU (TBB tiles, square ray packets) into a premultiplied
 * RGBA + depth frame that is drawn into the OpenGL framebuffer writing depth, so the
 * spheres hide and are hidden by ordinary geometry.
 *
 * Two accelerators answer the same closest-hit queries: the coherent grid traversal of
 * Gribble et al. 2007 (default: a multi-level grid with the sphere-center method, square
 * ray packets walking it slice by slice) and Embree's sphere-point BVH (the reference).
 *
 * Bad input never poisons the image: points with NaN/Inf coordinates, and spheres whose
 * radius is NaN, infinite, zero, negative or above 1e15, are skipped with one warning naming
 * how many; a radius array that is missing falls back to the constant radius with a
 * warning. A NaN colour scalar is coloured with the lookup table's NaN colour (as every VTK
 * mapper colours it); the sphere is drawn.
 * Numeric properties reject NaN and infinity and clamp out-of-range values, each with one
 * warning (vtkRayMapperSetGet.h; lengths up to 1e15); an array of several components read
 * as a scalar gives its first component (one warning when they differ); a degenerate camera
 * (the eye at the focal point, a NaN position) gives one warning and nothing drawn.
 *
 * Translucency: every sphere's opacity is the actor's Opacity times, when OpacityArray names
 * a numeric point array, its component OpacityArrayComponent mapped through
 * ScalarOpacityFunction (vtkPointGaussianMapper's names and rule). Translucent spheres are
 * composited exactly by the ray tracer, front to back along every ray, each sphere once
 * at its front surface, with early termination within 1/512 of the exact composite
 * (SphereRenderer.h); the frame is blended over what is drawn, premultiplied, and the rays
 * stop at the depth of the opaque geometry drawn before. Shadow and ambient-occlusion rays
 * see every sphere as opaque. The actor is then drawn in VTK's translucent pass (the
 * mapper says HasTranslucentPolygonalGeometry when the opacity array is in use; vtkActor
 * itself when Opacity < 1). There the mapper only notes the actor: VTK's translucent pass
 * (order-independent blending or depth peeling) composites through shader code that a
 * frame drawn by a quad has no part in, so the translucent spheres are drawn when the
 * renderer's render ends (its EndEvent), blended over everything it drew, opaque and
 * translucent: other translucent geometry shows behind the spheres wherever it is, and
 * 2D props of the same renderer (a scalar bar) are drawn over too; the rays stop at the
 * opaque geometry's depth, so the spheres are exact against opaque geometry. A renderer
 * whose image is read before its render ends (a compositing pass: IceT under MPI) needs
 * a vtkCGTSphereOverlayProp of this mapper in it, which draws them in its overlay step.
 * With Opacity 1 and no opacity array the opaque closest-hit path runs (effect
 * "translucency" off). A NaN opacity value hides its sphere (one warning per input change);
 * a missing or non-numeric opacity array, or a component beyond its components, gives one
 * warning and the actor's opacity alone.
 *
 * After each render, GetStatistics() reports the time per phase, the counters (rays,
 * hits, spheres) and which effects ran.
 */
#ifndef vtkCGTSphereMapper_h
#define vtkCGTSphereMapper_h

#include "RayMappersMappersModule.h" // for export macro
#include "vtkPolyDataMapper.h"
#include "vtkRayMapperParticleSizes.h" // for SphereRadiusPerSpacing
#include "vtkRayMapperSetGet.h"        // for vtkRayMapperSetClampMacro

#include <cstdint> // for std::uint64_t
#include <memory>  // for std::unique_ptr

class vtkDataArray;
class vtkPiecewiseFunction;
class vtkHardwareSelector;
class vtkIdTypeArray;
class vtkRayMapperStatistics;
struct vtkRayMapperView;
namespace vtkRayMapperRenderHelpers
{
struct ModelTransform;
}
namespace raymappers
{
class RenderStatistics;
class SphereAccelerator;
struct SphereShading;
}

#define VTK_CGT_ACCELERATOR_GRID 0
#define VTK_CGT_ACCELERATOR_EMBREE 1
#define VTK_CGT_ACCELERATOR_AUTOMATIC 2

#define VTK_CGT_SIMD_AUTO 0
#define VTK_CGT_SIMD_PORTABLE 1
#define VTK_CGT_SIMD_AVX2 2
#define VTK_CGT_SIMD_AVX512 3

class RAYMAPPERSMAPPERS_EXPORT vtkCGTSphereMapper : public vtkPolyDataMapper
{
public:
  static vtkCGTSphereMapper* New();
  vtkTypeMacro(vtkCGTSphereMapper, vtkPolyDataMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Constant radius, used when no radius array is selected (or it is missing).
   * Default 0: automatic, GetAutomaticRadiusPerSpacing() (0.5) times the typical spacing of
   * the input's points (1% of the bounds' diagonal when there is no spacing, e.g. one point).
   */
  vtkRayMapperSetClampMacro(Radius, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(Radius, double);
  static double GetAutomaticRadiusPerSpacing()
  {
    return vtkRayMapperParticleSizes::SphereRadiusPerSpacing;
  }
  ///@}

  /** The constant radius the spheres get for the current input: Radius, or the automatic
   * one when Radius is 0 (before ScaleFactor). */
  double GetRadiusInUse();

  ///@{
  /**
   * ScaleArray: a point array giving each sphere's radius (its first component, so the
   * 3-component "radius" of vtkPDBReader works as is); nullptr (default) means the constant
   * Radius for all. ScaleFactor: a factor applied to every radius (constant or from the
   * array), default 1. vtkPointGaussianMapper's names.
   */
  vtkRayMapperScaleMacro();
  ///@}

  ///@{
  /** @deprecated RadiusArrayName and RadiusScale (vtkRayMapperDeprecatedRadiusNamesMacro). */
  vtkRayMapperDeprecatedRadiusNamesMacro();
  ///@}

  ///@{
  /**
   * Per-sphere opacity (vtkPointGaussianMapper's names): OpacityArray, a numeric point
   * array (nullptr, the default: none), its component OpacityArrayComponent (default 0),
   * mapped through ScalarOpacityFunction (nullptr: the value itself), clamped to [0, 1] and
   * multiplied by the actor's Opacity.
   */
  vtkSetStringMacro(OpacityArray);
  vtkGetStringMacro(OpacityArray);
  vtkRayMapperSetClampMacro(OpacityArrayComponent, int, 0, VTK_INT_MAX);
  vtkGetMacro(OpacityArrayComponent, int);
  void SetScalarOpacityFunction(vtkPiecewiseFunction* function);
  vtkGetObjectMacro(ScalarOpacityFunction, vtkPiecewiseFunction);
  ///@}

  ///@{
  /**
   * Whether the spheres are opaque or translucent for VTK's render passes: translucent when
   * OpacityArray names a numeric point array of the input (vtkActor adds its own Opacity);
   * the lookup table's alpha, which the spheres do not draw, is not looked at.
   */
  bool HasOpaqueGeometry() override;
  bool HasTranslucentPolygonalGeometry() override;
  ///@}

  ///@{
  /**
   * Side of the square screen tiles handed to the TBB scheduler, in pixels
   * (clamped to [4, 256]). Any tile size gives the same picture. Default 32.
   */
  vtkRayMapperSetClampMacro(TileSize, int, 4, 256);
  vtkGetMacro(TileSize, int);
  ///@}

  ///@{
  /**
   * The accelerator: VTK_CGT_ACCELERATOR_AUTOMATIC (default: the coherent grid, unless its
   * occupancy shows it failed to separate the spheres, more than 1% of them in leaves of more
   * than 1024, where Embree's BVH is built instead; counters "accelerator_embree" and
   * "grid_crowded_spheres" say which ran and why), VTK_CGT_ACCELERATOR_GRID (always the grid)
   * or VTK_CGT_ACCELERATOR_EMBREE (always Embree). All give the same picture.
   */
  vtkRayMapperSetClampMacro(
    Accelerator, int, VTK_CGT_ACCELERATOR_GRID, VTK_CGT_ACCELERATOR_AUTOMATIC);
  vtkGetMacro(Accelerator, int);
  void SetAcceleratorToAutomatic() { this->SetAccelerator(VTK_CGT_ACCELERATOR_AUTOMATIC); }
  void SetAcceleratorToCoherentGrid() { this->SetAccelerator(VTK_CGT_ACCELERATOR_GRID); }
  void SetAcceleratorToEmbree() { this->SetAccelerator(VTK_CGT_ACCELERATOR_EMBREE); }
  ///@}

  ///@{
  /**
   * Side of the square ray packets of the coherent grid traversal, 1 to 16. Default 8.
   */
  vtkRayMapperSetClampMacro(PacketSize, int, 1, 16);
  vtkGetMacro(PacketSize, int);
  ///@}

  ///@{
  /**
   * Grid cells per sphere (the grid has about Lambda * N cubic cells; a cell crowded with
   * more than 64 spheres, as clustered data has, is a nested grid of about Lambda subcells
   * per sphere; counter "grid_nested_cells"). Default 1.
   */
  vtkRayMapperSetClampMacro(Lambda, double, 0.01, 100.0);
  vtkGetMacro(Lambda, double);
  ///@}

  ///@{
  /**
   * Cells per side of a macrocell, the grid's empty-space level. Default 6.
   */
  vtkRayMapperSetClampMacro(MacrocellSize, int, 1, 64);
  vtkGetMacro(MacrocellSize, int);
  ///@}

  ///@{
  /**
   * Ambient occlusion: rays per visible point (0, the default, turns it off; at most 256),
   * cosine-distributed over the hemisphere of the normal; the fraction that meets no
   * sphere within AmbientOcclusionRadius scales the shaded colour. A radius of 0 (default)
   * means twice the largest sphere radius.
   */
  vtkRayMapperSetClampMacro(AmbientOcclusionSamples, int, 0, 256);
  vtkGetMacro(AmbientOcclusionSamples, int);
  vtkRayMapperSetClampMacro(AmbientOcclusionRadius, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(AmbientOcclusionRadius, double);
  ///@}

  ///@{
  /**
   * Progressive ambient occlusion: at most this many of the AmbientOcclusionSamples
   * directions per visible point are traced in one render (0, the default: all of them in
   * every render, as without accumulation; above AmbientOcclusionSamples: all in the first
   * render; clamped to [0, 256] with one warning). While nothing that changes the image
   * changes (camera, window size, lights, data, colours, any property of the mapper or
   * actor), each render adds the next directions of the same fixed sequence and shades with
   * the unoccluded share of all traced so far; once all are in, the image equals a one-shot
   * render bit for bit, and further renders trace no occlusion ray (a plain frame's cost).
   * Any change starts again from the first directions. Translucent spheres trace all
   * directions in every render.
   *
   * A still camera is refined only by further renders: in a VTK pipeline, call the window's
   * Render() until GetAmbientOcclusionConverged() is true; in pvpython, call Render() of the
   * view in such a loop; the ParaView GUI renders on demand (an interaction, a property
   * change) and does not render again by itself. The statistics count "ao_samples_done"
   * (directions per point accumulated after the render) and "ao_converged". A
   * vtkWindowToImageFilter with ShouldRerender on renders with a projection matrix that
   * differs in its last digits (3e-8 relative, seen at 1024^2), a change that starts again:
   * grab a converged window with ShouldRerenderOff. ParaView's SaveScreenshot keeps the
   * accumulation (Testing/Python/TestRayTracedSpheresRepresentation.py).
   */
  vtkRayMapperSetClampMacro(AmbientOcclusionSamplesPerFrame, int, 0, 256);
  vtkGetMacro(AmbientOcclusionSamplesPerFrame, int);
  /** Whether the last render's ambient occlusion has all its directions (true when it is
   * off, or nothing was rendered): further renders with the same view would not change it. */
  bool GetAmbientOcclusionConverged();
  ///@}

  ///@{
  /**
   * Soft shadows from a square area light (Gribble et al., section 4.3): ShadowRays x
   * ShadowRays shadow rays per visible point (0, the default, turns shadows off; 1 gives a
   * hard shadow; at most 16). When on, this light replaces the renderer's lights; the
   * ambient term stays. With AutomaticShadowLight (default on) the light sits above and in
   * front of the data (centre + (0.5, 1, 0.8) x the bounds diagonal, edge 0.15 diagonal);
   * otherwise at ShadowLightPosition (world) with edge ShadowLightSize, facing the data's
   * centre.
   */
  vtkRayMapperSetClampMacro(ShadowRays, int, 0, 16);
  vtkGetMacro(ShadowRays, int);
  vtkSetMacro(AutomaticShadowLight, bool);
  vtkGetMacro(AutomaticShadowLight, bool);
  vtkBooleanMacro(AutomaticShadowLight, bool);
  vtkRayMapperSetVector3ClampMacro(ShadowLightPosition,
    double,
    -VTK_RAYMAPPER_LENGTH_MAX,
    VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetVector3Macro(ShadowLightPosition, double);
  vtkRayMapperSetClampMacro(ShadowLightSize, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(ShadowLightSize, double);
  vtkRayMapperSetClampMacro(ShadowLightIntensity, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(ShadowLightIntensity, double);
  ///@}

  ///@{
  /**
   * Build quality of Embree's BVH: 0 low (fast build, for time steps), 1 medium (default),
   * 2 high (slow build, fastest traversal, for static scenes).
   */
  vtkRayMapperSetClampMacro(EmbreeBuildQuality, int, 0, 2);
  vtkGetMacro(EmbreeBuildQuality, int);
  ///@}

  ///@{
  /**
   * SIMD instructions of the grid's ray-sphere tests: VTK_CGT_SIMD_AUTO (default, the
   * widest the CPU has), _PORTABLE (plain C++), _AVX2 (8 rays at once), _AVX512 (16). A
   * request the CPU cannot run falls back to the widest it can; the "simd_lanes" counter
   * of the statistics says which ran. For benchmarks and checks; the image is the same.
   */
  vtkRayMapperSetClampMacro(SimdInstructions, int, VTK_CGT_SIMD_AUTO, VTK_CGT_SIMD_AVX512);
  vtkGetMacro(SimdInstructions, int);
  ///@}

  /**
   * Parameter-range culling (Gribble et al., section 4.3): range `index` (0 to 3) keeps only
   * the points whose point array `arrayName` (first component) lies in [minimum, maximum];
   * all set ranges must hold. A null or empty name clears the range. Changing the bounds
   * never rebuilds the accelerator (the grid's macrocells keep each array's extrema);
   * changing the array rebuilds the spheres.
   */
  void SetRange(int index, const char* arrayName, double minimum, double maximum);
  void RemoveAllRanges();

  ///@{
  /**
   * Hardware selection (vtkHardwareSelector: ParaView's Select Points On, Hover Points,
   * Interactive Select): a selection pass draws, for each pixel, the id of the point whose
   * sphere is in front (the cell selection passes: the id of its vertex cell; a point in no
   * vertex cell selects nothing). PointIdArrayName and ProcessIdArrayName name point arrays
   * (vtkIdTypeArray, vtkUnsignedIntArray) giving each point's id in, and the process of, the
   * data it was taken from, as for vtkOpenGLPolyDataMapper; unset (default) or absent: the
   * input's own ids.
   */
  vtkSetStringMacro(PointIdArrayName);
  vtkGetStringMacro(PointIdArrayName);
  vtkSetStringMacro(ProcessIdArrayName);
  vtkGetStringMacro(ProcessIdArrayName);
  ///@}

  ///@{
  /**
   * Highlighted points: the spheres of these point ids (nullptr or empty: none; ids outside
   * the input are ignored) get SelectionColor (default magenta, ParaView's) instead of their
   * colour, and are lit like the others. ParaView's Ray-Traced Spheres set them from the
   * view's selection, which ParaView draws as points that the spheres would hide.
   */
  void SetSelectedPoints(vtkIdTypeArray* pointIds);
  void SetSelectionColor(double r, double g, double b);
  void SetSelectionColor(const double rgb[3]) { this->SetSelectionColor(rgb[0], rgb[1], rgb[2]); }
  vtkGetVector3Macro(SelectionColor, double);
  ///@}

  /**
   * Draws now the translucent spheres of this render that wait for the end of the
   * renderer's render (see above), and returns whether there were any. For renderers whose
   * image is read before their render ends, as IceT's compositing pass does under MPI:
   * vtkCGTSphereOverlayProp calls it in the renderer's overlay step. Nothing happens for
   * another renderer or when nothing waits.
   */
  bool DrawDeferredSpheres(vtkRenderer* ren);

  ///@{
  /**
   * The box the primary rays see spheres in (xmin, xmax, ymin, ymax, zmin, zmax in model
   * coordinates; default: all of space). Distributed rendering with a volume in the view
   * sets it to the process's region of the partition (its spheres plus the neighbours' that
   * reach in), so that the regions' images, blended in visibility order, are the
   * one-process image (effect region_clip). Shadow and occlusion rays are not restricted.
   */
  vtkSetVector6Macro(RegionBounds, double);
  vtkGetVector6Macro(RegionBounds, double);
  ///@}

  /**
   * Statistics of the last render: phase times, counters, effects that ran.
   */
  vtkRayMapperStatistics* GetStatistics();

  ///@{
  /** NumberOfThreads (vtkRayMapperNumberOfThreadsMacro, vtkRayMapperSetGet.h). */
  vtkRayMapperNumberOfThreadsMacro();
  ///@}

  void RenderPiece(vtkRenderer* ren, vtkActor* act) override;
  void ReleaseGraphicsResources(vtkWindow* win) override;

protected:
  vtkCGTSphereMapper();
  ~vtkCGTSphereMapper() override;

  /// Bounds of the points grown by the largest radius, so a camera reset frames the spheres.
  void ComputeBounds() override;

  double Radius = 0.0;
  char* ScaleArray = nullptr;
  double ScaleFactor = 1.0;
  int TileSize = 32;
  int Accelerator = VTK_CGT_ACCELERATOR_AUTOMATIC;
  int PacketSize = 8;
  double Lambda = 1.0;
  int MacrocellSize = 6;
  int EmbreeBuildQuality = 1;
  int SimdInstructions = VTK_CGT_SIMD_AUTO;
  int AmbientOcclusionSamples = 0;
  int ShadowRays = 0;
  bool AutomaticShadowLight = true;
  double ShadowLightPosition[3] = { 0, 0, 0 };
  double ShadowLightSize = 1.0;
  double ShadowLightIntensity = 1.0;
  double AmbientOcclusionRadius = 0.0;
  int AmbientOcclusionSamplesPerFrame = 0;

  int NumberOfThreads = 0;
  char* OpacityArray = nullptr;
  int OpacityArrayComponent = 0;
  vtkPiecewiseFunction* ScalarOpacityFunction = nullptr;
  char* PointIdArrayName = nullptr;
  char* ProcessIdArrayName = nullptr;
  double SelectionColor[3] = { 1.0, 0.0, 1.0 };
  double RegionBounds[6] = { -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX,
    -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX };

private:
  vtkCGTSphereMapper(const vtkCGTSphereMapper&) = delete;
  /// Places the area light of the soft shadows into the kernel's shading input.
  void SetUpShadowLight(const vtkRayMapperRenderHelpers::ModelTransform& model,
    raymappers::SphereShading& shading);
  // The phases of RenderPiece: the sphere set (rebuilt or recoloured when its inputs
  // change), the accelerator over it (true: the coherent grid), the shading input, the
  // parameter ranges.
  struct SphereColors;
  void UpdateSpheres(vtkPolyData* input, vtkActor* actor, raymappers::RenderStatistics& stats);
  void BuildSpheres(vtkPolyData* input, const SphereColors& colorOf);
  void UpdateSelectedMask(vtkIdType numberOfPoints);
  void ReadRangeAttributes(vtkPolyData* input);
  /// The opacity array in use (nullptr: none), with one warning per input change when it
  /// is named but missing or not numeric (`warn`).
  vtkDataArray* FindOpacityArray(vtkPolyData* input, bool warn);
  void UpdateOpacities(vtkPolyData* input, raymappers::RenderStatistics& stats);
  bool UpdateAccelerator(raymappers::RenderStatistics& stats);
  // The builds of UpdateAccelerator: the grid (false when the automatic choice rejects it
  // for its crowded leaves), Embree's BVH.
  bool BuildGrid(raymappers::RenderStatistics& stats);
  void BuildEmbree(raymappers::RenderStatistics& stats);
  void GatherShading(vtkRenderer* ren,
    vtkActor* actor,
    const vtkRayMapperRenderHelpers::ModelTransform& model,
    raymappers::SphereShading& shading);
  void SetRangeFilter(raymappers::SphereAccelerator& accelerator);
  /// A number that changes whenever the spheres or their colours may have (progressive
  /// ambient occlusion starts again).
  std::uint64_t SceneVersion(vtkActor* actor);
  void operator=(const vtkCGTSphereMapper&) = delete;

  /// One render, in the mapper's task arena (RenderPiece runs it there): an image, or in a
  /// hardware selection pass (vtkRayMapperSelectionPass.h) the ids of the spheres in front:
  /// point ids for point selection, the ids of their vertex cells for cell selection.
  void RenderFrame(vtkRenderer* ren, vtkActor* actor);
  /// After a render that ran out of memory: the spheres and accelerators freed, their
  /// stamps invalidated (the next render builds them again).
  void ReleaseBuilds();
  /// The renderer's EndEvent: the translucent frame RenderPiece deferred.
  void DrawDeferred(vtkObject* caller, unsigned long event, void* data);
  /// The updated spheres and accelerator (range filter set) and the camera of a render; null
  /// when there is nothing to draw.
  raymappers::SphereAccelerator* PrepareScene(vtkRenderer* ren,
    vtkActor* actor,
    vtkRayMapperView& view,
    raymappers::RenderStatistics& stats);
  /// The last selection pass's picks drawn as the ids of the selector's pass.
  void PresentSelection(vtkRenderer* ren,
    vtkHardwareSelector* selector,
    raymappers::RenderStatistics& stats);
  /// The last selection pass's point ids replaced by their vertex cells' ids; returns the
  /// largest cell id.
  vtkIdType PicksToVertexCells(vtkPolyData* input);

  struct Internals;
  std::unique_ptr<Internals> Impl;
};

#endif
