/**
 * @class   vtkSPHFluidRepresentation
 * @brief   ParaView representation "SPH Fluid": the points of the data as SPH particles
 *          rendered as a homogeneous fluid (surfaces, absorption, refraction, AO).
 *
 * Every point of the input (any vtkDataSet or composite of them; cells are ignored) is a
 * sphere of a constant radius or of a point array's value (times a scale); vtkSPHFluidMapper
 * voxelizes their union per frame (Zirr and Dachsbacher 2015) and renders its surfaces with
 * the view's lights (the light kit and the headlight) and the Ambient / Diffuse / Specular
 * settings, translucent with Beer-Lambert absorption (AbsorptionColor times Density per
 * LengthUnit), refracting when the index of refraction is not 1, with ambient occlusion when
 * asked. Coloring follows ParaView's rules as the surface representation's: a point array
 * (ColorArrayName) mapped through the LookupTable colors the particles, and the fluid the
 * normalized SPH average of their colors at its front surface (vtkSPHFluidMapper's
 * ScalarVisibility); otherwise the solid DiffuseColor.
 *
 * The particles, their radii (Radius, the radius array whenever one is selected,
 * RadiusScale) and the material come from vtkRayMapperParticleRepresentation.
 *
 * Like the other representations of this plugin it is added by the plugin's XML as a
 * sub-representation "SPH Fluid" of ParaView's composite representations.
 */
#ifndef vtkSPHFluidRepresentation_h
#define vtkSPHFluidRepresentation_h

#include "RayMappersRepresentationsModule.h" // for export macro
#include "vtkRayMapperParticleRepresentation.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

class vtkScalarsToColors;
class vtkSPHFluidMapper;
class vtkVolume;

class RAYMAPPERSREPRESENTATIONS_EXPORT vtkSPHFluidRepresentation
  : public vtkRayMapperParticleRepresentation
{
public:
  static vtkSPHFluidRepresentation* New();
  vtkTypeMacro(vtkSPHFluidRepresentation, vtkRayMapperParticleRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  //***************************************************************************
  // Forwarded to vtkSPHFluidMapper (see there).
  void SetAngleResolution(double degrees);
  void SetMaximumLayers(int layers);
  void SetMaximumSpans(int spans);
  void SetMemoryBudget(double megabytes);
  void SetLengthUnit(int unit);
  void SetGapThreshold(double g);
  void SetBoundaryCulling(bool on);
  void SetCellSize(double size);
  void SetSubsampling(int p);
  void SetFrameBudget(double seconds);
  /** The mapper's NumberOfThreads (its own TBB task arena; 0: the default). */
  void SetNumberOfThreads(int threads);
  void SetSmoothingRadius(double radius);
  void SetSmoothingIterations(int iterations);
  /** The solid color (ParaView's Solid Color): the mapper's Color. */
  void SetDiffuseColor(double r, double g, double b);
  /** The color map of the color array. */
  void SetLookupTable(vtkScalarsToColors* lut);
  ///@{
  /**
   * The highlights' strength (the volume property's Specular) is FluidSpecular (0.5 in the
   * XML: the water's highlights show), not the Specular ParaView shares with the surface
   * representation (0 by default), which the fluid ignores.
   */
  void SetFluidSpecular(double value);
  void SetSpecular(double) {}
  ///@}
  void SetTranslucency(bool on);
  void SetAbsorptionColor(double r, double g, double b);
  void SetDensity(double density);
  void SetRefractiveIndex(double eta);
  void SetBounces(int bounces);
  void SetAmbientOcclusion(bool on);
  void SetAmbientOcclusionRadius(double radius);
  void SetAmbientOcclusionSamples(int samples);

  ///@{
  /** The mapper and the volume, for tests and C++ users. */
  vtkSPHFluidMapper* GetMapper();
  vtkVolume* GetVolume();
  ///@}

protected:
  vtkSPHFluidRepresentation();
  ~vtkSPHFluidRepresentation() override;

  void PushRadius(double& radius, double& scale, const char* radiusArray) override;
  /// The mapper colors by the color array when a point array is selected.
  void UpdateMapperParameters() override;
  double GetAutomaticRadiusPerSpacing() override;
  Distribution GetDistribution() override { return Distribution::GatherToFirst; }

  vtkSmartPointer<vtkVolume> Volume;
  vtkSmartPointer<vtkSPHFluidMapper> Mapper;

private:
  vtkSPHFluidRepresentation(const vtkSPHFluidRepresentation&) = delete;
  void operator=(const vtkSPHFluidRepresentation&) = delete;
};

#endif
