/**
 * vtkRayMapperVolumeClassification: the classification the volume representations share
 * ("RBF Volume", "SPH Volume", "Z-Sweep Volume"): ParaView's color map of the color array
 * (LookupTable), its opacity map (ScalarOpacityFunction, else the one the color map carries)
 * and the distance over which the opacity map's opacity holds (ScalarOpacityUnitDistance);
 * without a classified array, the solid color with an opacity rising linearly from 0 at 0
 * to 1 at 1.
 *
 * A composed object rather than a base class: the particle volumes (RBF, SPH) derive from
 * vtkRayMapperParticleRepresentation, and the Z-Sweep volume, which classifies the same way,
 * is not a particle representation; no single-inheritance chain gives the classification to
 * all three and the particles only to the first two.
 */
#ifndef vtkRayMapperVolumeClassification_h
#define vtkRayMapperVolumeClassification_h

#include "vtkSmartPointer.h" // for vtkSmartPointer

class vtkColorTransferFunction;
class vtkObject;
class vtkPiecewiseFunction;
class vtkScalarsToColors;

class vtkRayMapperVolumeClassification
{
public:
  vtkRayMapperVolumeClassification();
  ~vtkRayMapperVolumeClassification();

  vtkSmartPointer<vtkScalarsToColors> LookupTable;
  vtkSmartPointer<vtkPiecewiseFunction> ScalarOpacity;

  /// Keeps `distance` when it is positive and finite; else warns from `self` and keeps the
  /// last one (false).
  bool SetScalarOpacityUnitDistance(vtkObject* self, double distance);
  double GetScalarOpacityUnitDistance() const { return this->UnitDistance; }

  /// The solid color, checked as DiffuseColor (warnings from `self`); false: rejected.
  bool SetSolidColor(vtkObject* self, double r, double g, double b);

  /// The color map: the LookupTable when it is a color transfer function, else null.
  vtkColorTransferFunction* GetColorMap() const;

  /// The opacity map: ScalarOpacity, else the one the color map carries, else null.
  vtkPiecewiseFunction* GetOpacityMap() const;

  /// The maps that classify the point array `valueArray` (null: none): its color and
  /// opacity maps, or the solid color and ramp when it has not both (with a warning from
  /// `self` when an array and a color map were given). Returns whether `valueArray` is
  /// classified by its maps; if not, the mapper takes no value array (every particle
  /// carries 1).
  bool Classify(vtkObject* self,
    const char* valueArray,
    vtkColorTransferFunction*& color,
    vtkPiecewiseFunction*& opacity) const;

private:
  double UnitDistance = 1.0;
  vtkSmartPointer<vtkColorTransferFunction> SolidColor;
  vtkSmartPointer<vtkPiecewiseFunction> SolidOpacity;
};

#endif
