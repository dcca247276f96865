/**
 * @class   vtkRBFVolumeRepresentation
 * @brief   ParaView representation "RBF Volume": the points of the data as a Gaussian RBF
 *          field, volume rendered.
 *
 * Every point of the input (any vtkDataSet or composite of them; cells are ignored) is a
 * particle whose Gaussian adds to a scalar field that vtkRBFVolumeMapper ray casts (Knoll
 * et al. 2014):
 *   Phi(x) = sum_i Kappa k_i exp(-|x - x_i|^2 / (2 r_i^2)),  truncated at Sigma r_i.
 * k_i is the value of the color array (ColorArrayName, a point array), r_i is
 * RadiusScale * (the radius array, or Radius).
 *
 * Classification uses ParaView's color map of the color array (LookupTable) and its opacity
 * map (ScalarOpacityFunction), the editors every ParaView volume uses; ScalarOpacityUnitDistance
 * is the distance over which the opacity map's opacity holds. With Shade on, the field's
 * analytic gradient lights the samples with the view's lights (Ambient, Diffuse, Specular,
 * SpecularPower). Without a color array every k_i is 1 and the field is shown in the solid
 * DiffuseColor with an opacity rising linearly from 0 at Phi = 0 to 1 at Phi = 1.
 *
 * Multi-field classification: with a FieldArray (a categorical point array, e.g. atom
 * types), its distinct values, in increasing order, split the particles into up to four
 * fields. Field 1 uses the LookupTable and ScalarOpacityFunction; fields 2 to 4 use the
 * color maps given as FieldLookupTable2 to FieldLookupTable4 (with their own opacity maps),
 * or the first field's maps when none is given.
 *
 * Changing Kappa, Sigma, SampleDistance, the maps or the lights never rebuilds the BVH;
 * only new data, new arrays or LeafSize do.
 *
 * The particles, their radii and the material come from vtkRayMapperParticleRepresentation,
 * the volume and its classification from vtkRayMapperParticleVolumeRepresentation.
 *
 * Like the "Ray-Traced Spheres" representation, it is added by the plugin's XML as a
 * sub-representation "RBF Volume" of ParaView's composite representations.
 */

#ifndef vtkRBFVolumeRepresentation_h
#define vtkRBFVolumeRepresentation_h

#include "RayMappersRepresentationsModule.h" // for export macro
#include "vtkRayMapperParticleVolumeRepresentation.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

#include <string> // for std::string

class vtkRBFVolumeMapper;

class RAYMAPPERSREPRESENTATIONS_EXPORT vtkRBFVolumeRepresentation
  : public vtkRayMapperParticleVolumeRepresentation
{
public:
  static vtkRBFVolumeRepresentation* New();
  vtkTypeMacro(vtkRBFVolumeRepresentation, vtkRayMapperParticleVolumeRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  //***************************************************************************
  // Multi-field classification.

  /**
   * Color maps (with their own opacity maps) of fields 2, 3 and 4; null: the first field's.
   */
  void SetFieldLookupTable2(vtkScalarsToColors* lut) { this->SetFieldLookupTable(1, lut); }
  void SetFieldLookupTable3(vtkScalarsToColors* lut) { this->SetFieldLookupTable(2, lut); }
  void SetFieldLookupTable4(vtkScalarsToColors* lut) { this->SetFieldLookupTable(3, lut); }

  /**
   * The categorical point array that splits the particles into fields. The first four
   * arguments are those of ParaView's array-selection properties and are ignored; empty or
   * "None": one field.
   */
  void SelectFieldArray(int, int, int, int, const char* name);

  //***************************************************************************
  // The field (forwarded to vtkRBFVolumeMapper, see there). Kappa 0 is the mapper's
  // automatic kappa; with several processes their measures are averaged (PushKappa).
  void SetKappa(double kappa);
  void SetSigma(double sigma);
  void SetSampleDistance(double distance);
  void SetTerminationOpacity(double opacity);
  void SetMethod(int method);
  void SetSamplesPerPass(int samples);

  /**
   * The value classified (vtkRBFVolumeMapper::NormalizeWeights): 0 the paper's sum of the
   * heights, 1 their weighted average with the opacity scaled by the particles' coverage,
   * 2 (Automatic, the default) the average when the field is coloured by an array and the
   * sum when it is not (every height 1: the sum is then the particles' density, the field
   * the paper shows). With ColorBy the colour map then reads the array's own values, where
   * the sum would mix them with the density and fill the bounds with the colour of 0 of a
   * signed array.
   */
  void SetNormalizeWeights(int mode);
  static constexpr int NormalizeWeightsAutomatic = 2;
  void SetPacketSize(int side);
  void SetLeafSize(int particles);
  /** The mapper's NumberOfThreads (its own TBB task arena; 0: the default). */
  void SetNumberOfThreads(int threads);

  /**
   * The mapper, for tests and C++ users.
   */
  vtkRBFVolumeMapper* GetMapper();

protected:
  vtkRBFVolumeRepresentation();
  ~vtkRBFVolumeRepresentation() override;

  void PushRadius(double& radius, double& scale, const char* radiusArray) override;
  double GetAutomaticRadiusPerSpacing() override;
  /** The field reaches Sigma radii beyond the points. */
  double GetParticleReach() override;
  void SetRegion(const double bounds[6]) override;
  void SetValueArray(const char* name) override;
  void UpdateMapperParameters() override;
  int GetNumberOfFields() override { return 4; }
  void GetFieldMaps(int field,
    vtkColorTransferFunction*& color,
    vtkPiecewiseFunction*& opacity) override;

  void SetFieldLookupTable(int field, vtkScalarsToColors* lut);

  vtkSmartPointer<vtkRBFVolumeMapper> Mapper;
  vtkSmartPointer<vtkScalarsToColors> FieldLookupTables[4];
  std::string FieldArrayName;
  double Kappa = 0.0;
  int NormalizeWeights = NormalizeWeightsAutomatic;

private:
  /// Hands Kappa to the mapper. The automatic kappa (Kappa 0) is 1 / a median weight sum
  /// that each process would measure on its own particles: with several processes (a
  /// collective call, made while rendering) the processes' weight sums are averaged, weighted
  /// by their particles, and all render with the same kappa.
  void PushKappa();
  /// Hands the mapper NormalizeWeights, resolving Automatic from its value array.
  void PushNormalizeWeights();
  vtkRBFVolumeRepresentation(const vtkRBFVolumeRepresentation&) = delete;
  void operator=(const vtkRBFVolumeRepresentation&) = delete;
};

#endif
