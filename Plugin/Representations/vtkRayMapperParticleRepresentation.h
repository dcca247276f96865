/**
 * @class   vtkRayMapperParticleRepresentation
 * @brief   What the particle representations share ("Ray-Traced Spheres", "RBF Volume",
 *          "SPH Volume", "SPH Fluid"): every point of the input is a particle of a radius,
 *          lit with one material.
 *
 * RequestData gathers the points and the point arrays of the input (any dataset or
 * composite of them; cells are ignored) into one vtkPolyData (vtkRayMapperGatherPoints),
 * which the view delivers; the delivered points go to the mapper the subclass names with
 * SetParticleMapper(), which then gets the settings that follow the input's arrays
 * (UpdateMapperParameters()).
 *
 * The particle radius r_i is RadiusScale * (the radius array's value at the point, when
 * UseRadiusArray is on and an array is selected, else Radius): the spheres' radius, the
 * Gaussians' radius, the SPH smoothing length h, the fluid spheres' radius. This class keeps
 * the settings as the mapper accepted them (PushRadius()). Radius 0 (the default) is
 * automatic: GetAutomaticRadiusPerSpacing() times the typical spacing of the particles
 * (vtkRayMapperParticleSizes), computed in RequestData on all of them: with several
 * processes the smallest of the processes' spacings (a process holding a spatial piece sees
 * the global spacing; one holding a random subset of n/p particles would overestimate it by
 * p^(1/3), which the minimum over processes does not correct), so that every process draws
 * the same radius. The rendered data reaches
 * GetParticleReach() radii beyond the points, which grows the bounds the view sees.
 *
 * Ambient, Diffuse, Specular and SpecularPower are the material of the prop's property (the
 * actor's vtkProperty or the volume's vtkVolumeProperty), checked alike: NaN and infinity
 * are rejected, values outside the range clamped, each with one warning.
 */

#ifndef vtkRayMapperParticleRepresentation_h
#define vtkRayMapperParticleRepresentation_h

#include "RayMappersRepresentationsModule.h" // for export macro
#include "vtkRayMapperParticleSizes.h" // for SpacingCache
#include "vtkRayMapperPropRepresentation.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

#include <string> // for std::string

class vtkAlgorithm;
class vtkPolyData;

class RAYMAPPERSREPRESENTATIONS_EXPORT vtkRayMapperParticleRepresentation
  : public vtkRayMapperPropRepresentation
{
public:
  vtkTypeMacro(vtkRayMapperParticleRepresentation, vtkRayMapperPropRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  //***************************************************************************
  // Particle size.

  ///@{
  /**
   * Radius of every particle when no radius array is used. Default 0: automatic (see above).
   */
  void SetRadius(double radius);
  double GetRadius() const { return this->Radius; }
  ///@}

  /**
   * The constant radius the mapper gets: Radius, or the automatic one when Radius is 0 (the
   * information property ...RadiusInUse of the panels).
   */
  double GetRadiusInUse() const;

  ///@{
  /**
   * Use the point array chosen with SelectRadiusArray() as the radius of each particle.
   */
  void SetUseRadiusArray(bool use);
  bool GetUseRadiusArray() const { return this->UseRadiusArray; }
  ///@}

  /**
   * Chooses the point array (1 component) giving each particle's radius. The first four
   * arguments (index, port, connection, field association) are those of ParaView's
   * array-selection properties and are ignored; empty or "None": no array.
   */
  void SelectRadiusArray(int, int, int, int, const char* name);
  const char* GetRadiusArrayName() const { return this->RadiusArrayName.c_str(); }

  ///@{
  /**
   * Factor applied to every radius (constant or from the array). Default 1.
   */
  void SetRadiusScale(double scale);
  double GetRadiusScale() const { return this->RadiusScale; }
  ///@}

  //***************************************************************************
  // Lighting, forwarded to the prop's property.
  void SetAmbient(double value);
  void SetDiffuse(double value);
  void SetSpecular(double value);
  void SetSpecularPower(double value);

protected:
  vtkRayMapperParticleRepresentation();
  ~vtkRayMapperParticleRepresentation() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  vtkDataSet* GetProcessedData() override;
  double GetBoundsMargin() override;
  void SetDeliveredPiece(vtkDataObject* piece) override;

  /**
   * The mapper that draws the particles (owned by the subclass): it gets the delivered
   * points (empty when nothing was delivered).
   */
  void SetParticleMapper(vtkAlgorithm* mapper) { this->ParticleMapper = mapper; }

  /**
   * Called once the mapper has the delivered points, before it renders: the settings that
   * follow the input's array selection (coloring, classification). Default: none.
   */
  virtual void UpdateMapperParameters() {}

  /**
   * Hands Radius, RadiusScale and the radius array in use (null: none) to the mapper and
   * returns in `radius` and `scale` the values it kept (it rejects NaN and clamps).
   */
  virtual void PushRadius(double& radius, double& scale, const char* radiusArray) = 0;

  /**
   * The automatic radius per typical particle spacing (the mapper's own factor).
   */
  virtual double GetAutomaticRadiusPerSpacing() = 0;

  /**
   * How far a particle's rendered geometry or field reaches, in radii (default 1).
   */
  virtual double GetParticleReach() { return 1.0; }

  /**
   * The radius array in use: the selected one when UseRadiusArray is on, else null.
   */
  const char* GetRadiusArrayInUse() const;

  /**
   * The point array the color array (SetInputArrayToProcess(0, ...)) names; null when none
   * is selected or it is not a point array (only point arrays color particles).
   */
  const char* GetColorPointArrayName();

  /**
   * Pushes the radius settings to the mapper (PushRadius) and keeps what it accepted, so that
   * a rejected value is warned about once, not again with every later radius setting; marks
   * the representation for a new RequestData (the automatic radius is measured there).
   */
  void UpdateRadiusParameters();

  vtkSmartPointer<vtkPolyData> ProcessedData;
  double Radius = 0.0;
  double RadiusScale = 1.0;
  bool UseRadiusArray = false;
  std::string RadiusArrayName;

private:
  /// Computes AutomaticRadius from ProcessedData when it is drawn (collective with several
  /// processes).
  void UpdateAutomaticRadius();
  /// Whether the mapper draws the automatic radius (collective with several processes).
  bool DrawsAutomaticRadius();
  /// Hands the radius settings in use to the mapper, keeping what it accepted.
  void PushRadiusInUse();

  vtkAlgorithm* ParticleMapper = nullptr;
  double AutomaticRadius = 0.0;
  vtkRayMapperParticleSizes::SpacingCache Spacing;
  /// The four material coefficients in the order of the lighting setters.
  enum class Material
  {
    Ambient,
    Diffuse,
    Specular,
    SpecularPower
  };
  void SetMaterial(Material coefficient, double value);

  vtkRayMapperParticleRepresentation(const vtkRayMapperParticleRepresentation&) = delete;
  void operator=(const vtkRayMapperParticleRepresentation&) = delete;
};

#endif
