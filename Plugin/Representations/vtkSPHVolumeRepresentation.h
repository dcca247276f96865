/**
 * @class   vtkSPHVolumeRepresentation
 * @brief   ParaView representation "SPH Volume": the points of the data as SPH particles,
 *          their field volume rendered directly.
 *
 * Every point of the input (any vtkDataSet or composite of them; cells are ignored) is an
 * SPH particle; vtkSPHVolumeMapper ray casts the SPH field of the color array's quantity
 * (Limper 2012), normalized by the sum of weights by default. The smoothing length comes
 * from an array or a constant, the particle volume from a volume array, from mass and
 * density arrays (V = m / rho) or a constant (1).
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
#include "vtkRayMapperPropRepresentation.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

class vtkColorTransferFunction;
class vtkPiecewiseFunction;
class vtkDataSet;
class vtkPolyData;
class vtkSPHVolumeMapper;
class vtkScalarsToColors;
class vtkVolume;
class vtkVolumeProperty;

class RAYMAPPERSREPRESENTATIONS_EXPORT vtkSPHVolumeRepresentation : public vtkRayMapperPropRepresentation
{
public:
  static vtkSPHVolumeRepresentation* New();
  vtkTypeMacro(vtkSPHVolumeRepresentation, vtkRayMapperPropRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  //***************************************************************************
  // Classification.
  /** Color map of the color array (a vtkColorTransferFunction, as ParaView's are). */
  void SetLookupTable(vtkScalarsToColors* lut);
  /** Opacity map of the color array. */
  void SetScalarOpacity(vtkPiecewiseFunction* opacity);
  /** Distance over which the opacity map's opacity holds (model units). */
  void SetScalarOpacityUnitDistance(double distance);

  //***************************************************************************
  // The particles and the field (forwarded to vtkSPHVolumeMapper, see there). The array
  // selectors take ParaView's five array-selection arguments, of which only the name is
  // used; empty or "None" means no array.
  void SetKernel(int kernel);
  void SetSupportFactor(double factor);
  void SetSmoothingLength(double h);
  void SelectSmoothingLengthArray(int, int, int, int, const char* name);
  void SetSmoothingLengthScale(double scale);
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
  void SetMaximumReduction(double r);
  void SetFrameBudget(double seconds);

  //***************************************************************************
  // Lighting and solid color, forwarded to the volume property.
  void SetShade(bool shade);
  void SetAmbient(double value);
  void SetDiffuse(double value);
  void SetSpecular(double value);
  void SetSpecularPower(double value);
  void SetDiffuseColor(double r, double g, double b);

  /** The mapper's statistics of the last render, one "kind name value" per line. */
  const char* GetRenderStatistics();

  ///@{
  /** The mapper, the volume and its property, for tests and C++ users. */
  vtkSPHVolumeMapper* GetMapper();
  vtkVolume* GetVolume();
  vtkVolumeProperty* GetVolumeProperty();
  ///@}

protected:
  vtkSPHVolumeRepresentation();
  ~vtkSPHVolumeRepresentation() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  vtkDataSet* GetProcessedData() override;
  double GetBoundsMargin() override;
  void SetDeliveredPiece(vtkDataObject* piece) override;
  Distribution GetDistribution() override { return Distribution::Particles; }
  void SetRegion(const double bounds[6]) override;

  /** Pushes the color array (the quantity Q) to the mapper and the maps to the property. */
  void UpdateClassification();

  vtkSmartPointer<vtkVolume> Volume;
  vtkSmartPointer<vtkSPHVolumeMapper> Mapper;
  vtkSmartPointer<vtkVolumeProperty> Property;
  vtkSmartPointer<vtkPolyData> ProcessedData;
  vtkSmartPointer<vtkScalarsToColors> LookupTable;
  vtkSmartPointer<vtkPiecewiseFunction> ScalarOpacity;
  // The classification without a color array: DiffuseColor, opacity ramp on [0, 1].
  vtkSmartPointer<vtkColorTransferFunction> SolidColor;
  vtkSmartPointer<vtkPiecewiseFunction> SolidOpacity;
  double ScalarOpacityUnitDistance = 1.0;

private:
  vtkSPHVolumeRepresentation(const vtkSPHVolumeRepresentation&) = delete;
  void operator=(const vtkSPHVolumeRepresentation&) = delete;
};

#endif
