/**
 * @class   vtkRayMapperParticleVolumeRepresentation
 * @brief   What the particle volumes share ("RBF Volume", "SPH Volume"): particles whose
 *          field is volume rendered in a vtkVolume, classified as any ParaView volume.
 *
 * The value of the color array (ColorArrayName, a point array) is the particles' quantity;
 * its color map (LookupTable) and opacity map (ScalarOpacityFunction, else the color map's
 * own) classify the field over ScalarOpacityUnitDistance (vtkRayMapperVolumeClassification).
 * Without a color array every particle carries 1 and the field is shown in the solid
 * DiffuseColor with an opacity rising linearly from 0 at 0 to 1 at 1. Shade lights the
 * samples with the field's gradient and the material (Ambient, Diffuse, Specular,
 * SpecularPower) of vtkRayMapperParticleRepresentation.
 *
 * Field m (0 to GetNumberOfFields() - 1) is classified with component m of the volume
 * property: the first field's maps, or those GetFieldMaps() gives for the others.
 */
#ifndef vtkRayMapperParticleVolumeRepresentation_h
#define vtkRayMapperParticleVolumeRepresentation_h

#include "RayMappersRepresentationsModule.h" // for export macro
#include "vtkRayMapperParticleRepresentation.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

#include <memory> // for std::unique_ptr

class vtkColorTransferFunction;
class vtkPiecewiseFunction;
class vtkRayMapperVolumeClassification;
class vtkScalarsToColors;
class vtkVolume;
class vtkVolumeProperty;

class RAYMAPPERSREPRESENTATIONS_EXPORT vtkRayMapperParticleVolumeRepresentation
  : public vtkRayMapperParticleRepresentation
{
public:
  vtkTypeMacro(vtkRayMapperParticleVolumeRepresentation, vtkRayMapperParticleRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  //***************************************************************************
  // Classification.

  /** Color map of the color array (a vtkColorTransferFunction, as ParaView's are). */
  void SetLookupTable(vtkScalarsToColors* lut);
  /** Opacity map of the color array. */
  void SetScalarOpacity(vtkPiecewiseFunction* opacity);
  /** Distance over which the opacity map's opacity holds (model units, positive). */
  void SetScalarOpacityUnitDistance(double distance);
  /** Light the samples with the field's gradient. */
  void SetShade(bool shade);
  /** The solid color, without a color array. */
  void SetDiffuseColor(double r, double g, double b);

  ///@{
  /** The volume and its property, for tests and C++ users. */
  vtkVolume* GetVolume();
  vtkVolumeProperty* GetVolumeProperty();
  ///@}

protected:
  vtkRayMapperParticleVolumeRepresentation();
  ~vtkRayMapperParticleVolumeRepresentation() override;

  Distribution GetDistribution() override { return Distribution::Particles; }

  /** Makes the volume drawn by `mapper` this representation's prop. */
  void SetVolumeMapper(vtkAbstractVolumeMapper* mapper);

  /** Hands the classified point array (null: none, every particle carries 1) to the mapper. */
  virtual void SetValueArray(const char* name) = 0;

  /** How many fields the volume property classifies (default 1). */
  virtual int GetNumberOfFields() { return 1; }

  /**
   * The maps of field `field` (1 or more) when the color array is classified; `color` and
   * `opacity` hold the first field's on entry (default: kept).
   */
  virtual void GetFieldMaps(int field,
    vtkColorTransferFunction*& color,
    vtkPiecewiseFunction*& opacity)
  {
  }

  /**
   * The classification: hands the color array to the mapper and the maps of every field,
   * with the unit distance, to the volume property.
   */
  void UpdateMapperParameters() override;

  vtkSmartPointer<vtkVolume> Volume;
  vtkSmartPointer<vtkVolumeProperty> Property;
  std::unique_ptr<vtkRayMapperVolumeClassification> Classification;

private:
  vtkRayMapperParticleVolumeRepresentation(
    const vtkRayMapperParticleVolumeRepresentation&) = delete;
  void operator=(const vtkRayMapperParticleVolumeRepresentation&) = delete;
};

#endif
