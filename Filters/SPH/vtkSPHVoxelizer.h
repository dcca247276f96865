/**
 * @class   vtkSPHVoxelizer
 * @brief   The view-adaptive voxelization of SPH particles (Zirr and Dachsbacher 2015) as
 *          an image: per pixel the depth spans of the fluid, their surface links and normals.
 *
 * Input: a vtkPointSet whose points are the particles, spheres of radius
 * r_i = ScaleFactor * (ScaleArray, else Radius). Output: a vtkImageData of
 * ImageSize[0] x ImageSize[1] x 1 points (spacing 1, origin 0; point (i, j) is pixel (i, j)
 * of the view, row 0 at the bottom), voxelized for a camera exactly as vtkSPHFluidMapper
 * does for a render of that size (same kernels: SpanVoxelizer.h, SurfaceLinks.h), with the
 * same settings: AngleResolution, MaximumLayers, MaximumSpans (S), MemoryBudget (MB),
 * GapThreshold, BoundaryCulling, CellSize, SmoothingRadius, SmoothingIterations.
 *
 * The camera: SetCamera(vtkCamera*) (e.g. a renderer's active camera; its MTime is
 * watched), or the filter's own camera set with SetCameraPosition / FocalPoint / ViewUp /
 * ViewAngle / ParallelProjection / ParallelScale. With ResetCamera on (default) a copy of
 * the camera is fitted to the particles as vtkRenderer::ResetCamera would (same direction,
 * view up and angle; the camera given is not changed); the clipping range is always fitted
 * to the particles unless ResetCamera is off and a camera was given (then its own is used).
 * The aspect ratio is the image's.
 *
 * Depth is zeta: for a perspective camera the distance from the eye plane along the view
 * direction, for a parallel one from the near plane (model units). A point at depth zeta on
 * pixel (i, j)'s ray is at distance zeta * DepthToDistance(i, j) from the ray's start.
 *
 * Point data (unused span slots hold NaN):
 *   SpanCount        (unsigned char)   spans stored for the pixel, 0..S
 *   SpansFound       (unsigned int)    spans along the whole ray (>= SpanCount: beyond S the
 *                                      last stored span is extended and its empty space kept)
 *   EntryDepth       (float, S comps)  zeta where span k begins
 *   ExitDepth        (float, S comps)  zeta where span k ends
 *   HiddenEmpty      (float)           zeta length of empty space inside the last stored span
 *   Thickness        (float)           fluid length along the ray in world units
 *                                      ((sum exit - entry) - HiddenEmpty) * DepthToDistance;
 *                                      the active scalars
 *   DepthToDistance  (float)           |d ray / d zeta| of the pixel's ray
 *   EntryNormal      (float, 3S comps) outward unit normal at entry k (x, y, z per span)
 *   ExitNormal       (float, 3S comps) outward unit normal at exit k
 *   Links            (unsigned int, 2S comps) the surface links of slot s (entry k: 2k,
 *                                      exit k: 2k + 1): bytes 0..3 for the neighbours +x, -x,
 *                                      +y, -y; a byte is the slot in that neighbour's
 *                                      column, or 0x80 | slot for a link within the pixel's
 *                                      own column (bubble walls; a boundary span's entry
 *                                      and exit link to each other), FluidSpans.h; 0 in
 *                                      unused slots
 * Field data: ModelToClip (16 doubles, row-major, the matrix used), LayerCount,
 * FirstLayerDepth, LastLayerDepth, LogarithmicLayers, AngleResolutionReached (degrees),
 * MaximumSpans.
 *
 * Bad input: particles with NaN/Inf coordinates or bad radii (NaN, infinite, zero, negative,
 * above 1e15) are skipped with a warning; numeric properties and the camera settings reject
 * NaN and infinity and clamp with a warning (vtkRayMapperSetGet.h); a degenerate camera
 * gives a warning and no spans; an
 * empty input gives an image without spans. GetStatisticsSummary() has the voxelizer's
 * phases and counters ("phase|counter|effect NAME VALUE" per line).
 */
#ifndef vtkSPHVoxelizer_h
#define vtkSPHVoxelizer_h

#include "RayMappersFiltersModule.h" // for export macro
#include "vtkRayMapperParticleSizes.h" // for SpacingCache
#include "vtkRayMapperSetGet.h" // for vtkRayMapperSetClampMacro
#include "vtkImageAlgorithm.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

#include <string> // for std::string

class vtkCamera;
class vtkPointSet;

class RAYMAPPERSFILTERS_EXPORT vtkSPHVoxelizer : public vtkImageAlgorithm
{
public:
  static vtkSPHVoxelizer* New();
  vtkTypeMacro(vtkSPHVoxelizer, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** Constant particle radius (default 0: automatic, as vtkSPHFluidMapper's, the typical
   * particle spacing), its point array, and a factor on either (1). */
  vtkRayMapperSetClampMacro(Radius, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(Radius, double);
  vtkRayMapperScaleMacro();
  ///@}

  /** The constant radius for `input`: Radius, or the automatic one when Radius is 0. */
  double GetRadiusInUse(vtkPointSet* input);

  /** @deprecated RadiusArrayName and RadiusScale (vtkRayMapperDeprecatedRadiusNamesMacro). */
  vtkRayMapperDeprecatedRadiusNamesMacro();

  ///@{
  /** The unit of GapThreshold, CellSize and SmoothingRadius, as vtkSPHFluidMapper's: the
   * particles' mean radius (PARTICLE_RADIUS, default; the same spans for the same particles
   * in other units) or the input's own unit (WORLD). */
  vtkRayMapperLengthUnitMacro();
  ///@}

  ///@{
  /** As vtkSPHFluidMapper: angle resolution (14 degrees), layers (16384), spans (7),
   * memory budget (0 MB: automatic, see vtkSPHFluidMapper), gap threshold (0), smoothing radius (0) and iterations (20). */
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
  vtkSetMacro(BoundaryCulling, bool);
  vtkGetMacro(BoundaryCulling, bool);
  vtkBooleanMacro(BoundaryCulling, bool);
  vtkRayMapperSetClampMacro(CellSize, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(CellSize, double);
  vtkRayMapperSetClampMacro(SmoothingRadius, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(SmoothingRadius, double);
  vtkRayMapperSetClampMacro(SmoothingIterations, int, 0, 1000);
  vtkGetMacro(SmoothingIterations, int);
  ///@}

  ///@{
  /** The image size in pixels (default 300 x 300). */
  vtkRayMapperSetVector2ClampMacro(ImageSize, int, 1, 16384);
  vtkGetVector2Macro(ImageSize, int);
  ///@}

  ///@{
  /** The camera (default: the filter's own, looking down -z). */
  void SetCamera(vtkCamera* camera);
  vtkCamera* GetCamera();
  ///@}

  ///@{
  /** The filter's camera settings (forwarded to the camera). */
  void SetCameraPosition(double x, double y, double z);
  void SetCameraFocalPoint(double x, double y, double z);
  void SetCameraViewUp(double x, double y, double z);
  void SetCameraViewAngle(double degrees);
  void SetCameraParallelProjection(bool parallel);
  void SetCameraParallelScale(double scale);
  ///@}

  ///@{
  /** Fit a copy of the camera (and the clipping range) to the particles (default on). */
  vtkSetMacro(ResetCamera, bool);
  vtkGetMacro(ResetCamera, bool);
  vtkBooleanMacro(ResetCamera, bool);
  ///@}

  /** The voxelizer's statistics of the last execution. */
  const char* GetStatisticsSummary();

  vtkMTimeType GetMTime() override;

protected:
  vtkSPHVoxelizer();
  ~vtkSPHVoxelizer() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double Radius = 0.0;
  int LengthUnit = PARTICLE_RADIUS;
  char* ScaleArray = nullptr;
  double ScaleFactor = 1.0;
  double AngleResolution = 14.0;
  int MaximumLayers = 16384;
  int MaximumSpans = 7;
  double MemoryBudget = 0.0;
  double GapThreshold = 0.0;
  bool BoundaryCulling = true;
  double CellSize = 0.0;
  double SmoothingRadius = 0.0;
  int SmoothingIterations = 20;
  int ImageSize[2] = { 300, 300 };
  bool ResetCamera = true;
  bool CameraGiven = false;
  vtkSmartPointer<vtkCamera> Camera;
  std::string Summary;

private:
  vtkRayMapperParticleSizes::SpacingCache Spacing;
  vtkSPHVoxelizer(const vtkSPHVoxelizer&) = delete;
  void operator=(const vtkSPHVoxelizer&) = delete;
};

#endif
