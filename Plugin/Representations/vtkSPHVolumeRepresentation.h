/**
 * @class   vtkSPHVolumeRepresentation
 * @brief   ParaView representation "SPH Volume": the points of the data as SPH particles,
 *          their field volume rendered directly.
 *
 * Every point of the input (any vtkDataSet or composite of them; cells are ignored) is an
 * SPH particle; vtkSPHVolumeMapper ray casts the SPH field of the color array's quantity
 * (Limper 2012), normalized by the sum of weights by default. The smoothing length comes
 * from an array or a constant, the particle volume from a volume array, from mass and
 * density arrays (V = m / rho) or a constant (1). The smoothing length h is the particle
 * radius of vtkRayMapperParticleRepresentation (SetRadius, SelectRadiusArray,
 * SetRadiusScale; the XML names them SPHSmoothingLength...); the field reaches one kernel
 * support, SupportFactor * h or the kernel's own support per smoothing length (SPHKernels.h),
 * beyond the points.
 *
 * Classification uses ParaView's color map of the color array (LookupTable) and its opacity
 * map (ScalarOpacityFunction), with ScalarOpacityUnitDistance; Shade lights the samples with
 * the field's exact gradient. Without a color array every particle carries 1 and the field
 * is shown in the solid DiffuseColor with an opacity rising from 0 at 0 to 1 at 1.
 *
 * Like the other representations of this plugin it is added by the plugin's XML as a
 * sub-representation "SPH Volume" of ParaView's composite representations.
 */
#ifndef vtkSPHVolumeRepresentation_h
#define vtkSPHVolumeRepresentation_h

#include "RayMappersRepresentationsModule.h" // for export macro
#include "vtkRayMapperParticleVolumeRepresentation.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

class vtkSPHVolumeMapper;

class RAYMAPPERSREPRESENTATIONS_EXPORT vtkSPHVolumeRepresentation
  : public vtkRayMapperParticleVolumeRepresentation
{
public:
  static vtkSPHVolumeRepresentation* New();
  vtkTypeMacro(vtkSPHVolumeRepresentation, vtkRayMapperParticleVolumeRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  //***************************************************************************
  // The particles and the field (forwarded to vtkSPHVolumeMapper, see there). The array
  // selectors take ParaView's five array-selection arguments, of which only the name is
  // used; empty or "None" means no array.
  void SetKernel(int kernel);
  void SetSupportFactor(double factor);
  void SelectMassArray(int, int, int, int, const char* name);
  void SelectDensityArray(int, int, int, int, const char* name);
  void SelectVolumeArray(int, int, int, int, const char* name);
  void SetParticleVolume(double volume);
  void SetNormalization(int mode);
  void SetContourShading(bool on);
  void SetContourColor(double r, double g, double b);
  void SetContourOpacity(double opacity);
  void SetStepFactor(double factor);
  void SetSamplesPerSupport(double samples);
  void SetTileSize(int pixels);
  void SetSlabDepth(int samples);
  void SetTerminationOpacity(double opacity);
  void SetJitter(bool on);
  void SetMaximumImageSampleDistance(double d);
  void SetFrameBudget(double seconds);
  /** The mapper's NumberOfThreads (its own TBB task arena; 0: the default). */
  void SetNumberOfThreads(int threads);

  /** The mapper, for tests and C++ users. */
  vtkSPHVolumeMapper* GetMapper();

protected:
  vtkSPHVolumeRepresentation();
  ~vtkSPHVolumeRepresentation() override;

  void PushRadius(double& radius, double& scale, const char* radiusArray) override;
  double GetAutomaticRadiusPerSpacing() override;
  /** The kernel's support in smoothing lengths. */
  double GetParticleReach() override;
  void SetRegion(const double bounds[6]) override;
  /// With several processes: also gives the mapper the smallest support of all of them
  /// (vtkSPHVolumeMapper::SetSmallestSupport), so that they all sample the same depths.
  void SetDeliveredPiece(vtkDataObject* piece) override;
  bool GetLastFrame(double frame[2]) override;
  void SetLastFrame(const double frame[2]) override;
  void SetValueArray(const char* name) override;

  vtkSmartPointer<vtkSPHVolumeMapper> Mapper;

private:
  vtkSPHVolumeRepresentation(const vtkSPHVolumeRepresentation&) = delete;
  void operator=(const vtkSPHVolumeRepresentation&) = delete;
};

#endif
