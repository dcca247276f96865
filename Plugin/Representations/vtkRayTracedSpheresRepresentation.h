/**
 * @class   vtkRayTracedSpheresRepresentation
 * @brief   ParaView representation "Ray-Traced Spheres": every point of the data as a sphere.
 *
 * Renders each point of its input with vtkCGTSphereMapper (an exact, lit, CPU ray-traced
 * sphere). The input may be any vtkDataSet (polygonal data, unstructured and structured
 * grids, point clouds ...) or a composite dataset of them, e.g. a multiblock from an
 * Exodus reader: all the points of all the leaves become spheres, not only the points on
 * the surface (unlike the "Surface" or "Points" representations, which show the outer
 * surface of a volumetric grid). Cells are ignored.
 *
 * RequestData() gathers the points and the point data of the input into one vtkPolyData
 * (points only, no cells; the point arrays common to all the leaves; points flagged as
 * duplicate or hidden ghosts are dropped), which is what the view delivers to the
 * rendering processes and what GetRenderedDataObject() reports.
 *
 * Coloring follows ParaView's usual rules (ColorArrayName + LookupTable + MapScalars, or
 * the solid DiffuseColor when no point array is selected; cell arrays cannot color
 * points, the solid color is used then). Lighting comes from the actor's vtkProperty
 * (Ambient, Diffuse, Specular, SpecularPower, SpecularColor). Translucency as Point
 * Gaussian's: Opacity, and with OpacityByArray the OpacityArray (its component
 * OpacityArrayComponent) through the OpacityTransferFunction; the mapper composites
 * translucent spheres exactly and the actor is drawn in the translucent pass then
 * (vtkCGTSphereMapper), opaque otherwise.
 *
 * The sphere radius is RadiusScale * (UseRadiusArray ? the value of the selected
 * 1-component point array : Radius) (vtkRayMapperParticleRepresentation).
 *
 * This representation is not meant to be created on its own: the server-manager XML of
 * the plugin adds it as a sub-representation "Ray-Traced Spheres" of ParaView's
 * GeometryRepresentation, UnstructuredGridRepresentation and StructuredGridRepresentation.
 */

#ifndef vtkRayTracedSpheresRepresentation_h
#define vtkRayTracedSpheresRepresentation_h

#include "RayMappersRepresentationsModule.h" // for export macro
#include "vtkRayMapperParticleRepresentation.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

#include <string> // for std::string

class vtkActor;
class vtkCGTSphereMapper;
class vtkCGTSphereOverlayProp;
class vtkDataSet;
class vtkIdTypeArray;
class vtkPiecewiseFunction;
class vtkPolyData;
class vtkScalarsToColors;

class RAYMAPPERSREPRESENTATIONS_EXPORT vtkRayTracedSpheresRepresentation
  : public vtkRayMapperParticleRepresentation
{
public:
  static vtkRayTracedSpheresRepresentation* New();
  vtkTypeMacro(vtkRayTracedSpheresRepresentation, vtkRayMapperParticleRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  //***************************************************************************
  // Coloring.

  /**
   * Lookup table used to map the color array to colors.
   */
  void SetLookupTable(vtkScalarsToColors* lut);

  /**
   * 1: map scalars through the lookup table; 0: use unsigned char / [0,1] float arrays
   * with up to 4 components directly as colors.
   */
  void SetMapScalars(int val);

  //***************************************************************************
  // Accelerator (forwarded to vtkCGTSphereMapper, see there).
  void SetAccelerator(int accelerator);
  void SetPacketSize(int side);
  /** The mapper's NumberOfThreads (its own TBB task arena; 0: the default). */
  void SetNumberOfThreads(int threads);
  void SetLambda(double lambda);
  void SetMacrocellSize(int cells);
  void SetAmbientOcclusionSamples(int samples);
  void SetAmbientOcclusionRadius(double radius);
  void SetAmbientOcclusionSamplesPerFrame(int samples);
  void SetShadowRays(int side);
  void SetAutomaticShadowLight(bool automatic);
  void SetShadowLightPosition(double x, double y, double z);
  void SetShadowLightSize(double size);
  void SetShadowLightIntensity(double intensity);

  /**
   * Parameter-range culling of the panel: four ranges (the mapper's slots 0 to 3), each on
   * the point array chosen with SelectRangeArray(slot, ..., name) (empty or "None": off)
   * between the bounds of SetRange1 to SetRange4.
   */
  void SelectRangeArray(int slot, int, int, int, const char* name);
  void SetRange1(double minimum, double maximum) { this->SetRangeBounds(0, minimum, maximum); }
  void SetRange2(double minimum, double maximum) { this->SetRangeBounds(1, minimum, maximum); }
  void SetRange3(double minimum, double maximum) { this->SetRangeBounds(2, minimum, maximum); }
  void SetRange4(double minimum, double maximum) { this->SetRangeBounds(3, minimum, maximum); }

  //***************************************************************************
  // Forwarded to the actor's vtkProperty (the lighting coefficients: see the superclass).
  virtual void SetAmbientColor(double r, double g, double b);
  virtual void SetDiffuseColor(double r, double g, double b);
  virtual void SetSpecularColor(double r, double g, double b);
  virtual void SetOpacity(double val);

  ///@{
  /**
   * Opacity by array, as vtkPointGaussianRepresentation: with OpacityByArray the point
   * array chosen with SelectOpacityArray (its component SelectOpacityArrayComponent)
   * through the OpacityTransferFunction gives each sphere its opacity (times Opacity).
   */
  void SetOpacityByArray(bool byArray);
  void SelectOpacityArray(int, int, int, int, const char* name);
  void SelectOpacityArrayComponent(int component);
  void SetOpacityTransferFunction(vtkPiecewiseFunction* function);
  ///@}

  ///@{
  /**
   * The mapper and the actor, for tests and for C++ users.
   */
  vtkCGTSphereMapper* GetMapper();
  vtkActor* GetActor();
  ///@}

  /**
   * The view's render request also highlights the selected spheres
   * (UpdateSelectionHighlight).
   */
  int ProcessViewRequest(vtkInformationRequestKey* request_type,
    vtkInformation* inInfo,
    vtkInformation* outInfo) override;

protected:
  vtkRayTracedSpheresRepresentation();
  ~vtkRayTracedSpheresRepresentation() override;

  /**
   * ParaView shows a selection by a selection representation that draws the extracted
   * points (vtkPVExtractSelection of this representation's input) as points, which the
   * spheres around them hide. So the mapper colours the spheres of those points
   * (vtkOriginalPointIds of this process's extraction) in that representation's colour
   * (ParaView's SelectionColor); no visible selection representation: no highlight. With a
   * piece exchanged between processes (see vtkRayMapperPropRepresentation), the processes
   * share their selections and each colours the spheres whose origin was selected:
   * collective then.
   */
  void UpdateSelectionHighlight();

  /**
   * With several rendering processes: opaque spheres are Surfaces (depth composited alone,
   * drawn per region of the partition when a volume shares the view); translucent ones
   * (Opacity below 1, or OpacityByArray with an array) and those with soft shadows or
   * ambient occlusion are Particles, blended in visibility order like a volume (see
   * vtkRayMapperPropRepresentation): each process draws its box, and its secondary rays see
   * the ghosts GetGhostMargin() brings.
   */
  Distribution GetDistribution() override;
  /**
   * The ghosts a process needs: the spheres reaching into its box (the largest radius r);
   * with ambient occlusion also those an occlusion ray from its box can meet (r + the
   * occlusion radius, 2 r when automatic); with soft shadows all spheres (a shadow ray may
   * cross the whole data: every process then holds every sphere).
   */
  double GetGhostMargin() override;
  /**
   * The actor and the vtkCGTSphereOverlayProp that draws its translucent spheres before a
   * compositing pass reads the image.
   */
  bool AddToView(vtkView* view) override;
  bool RemoveFromView(vtkView* view) override;
  void SetRegion(const double bounds[6]) override;

  void UpdateMapperParameters() override;
  void PushRadius(double& radius, double& scale, const char* radiusArray) override;
  double GetAutomaticRadiusPerSpacing() override;

  /**
   * Pushes the color array selection (SetInputArrayToProcess(0, ...)) to the mapper.
   */
  void UpdateColoringParameters();

  vtkSmartPointer<vtkActor> Actor;
  vtkSmartPointer<vtkCGTSphereMapper> Mapper;
  // Draws translucent spheres inside the render, where IceT's compositing sees them.
  vtkSmartPointer<vtkCGTSphereOverlayProp> Overlay;
  std::string RangeArrayNames[4];
  double RangeBounds[4][2] = { { 0, 1 }, { 0, 1 }, { 0, 1 }, { 0, 1 } };
  void SetRangeBounds(int slot, double minimum, double maximum);
  // The opacity array chosen in the panel, given to the mapper while OpacityByArray is on.
  bool OpacityByArray = false;
  std::string OpacityArrayName;
  int OpacityArrayComponent = 0;
  void UpdateOpacityArray();
  void UpdateRange(int slot);
  // The panel's AmbientOcclusionRadius (0: automatic, twice the largest radius of all the
  // processes' spheres when they exchange them).
  double AmbientOcclusionRadius = 0.0;
  // With a piece exchanged: the highlighted spheres of the last exchange of the selections,
  // and what it was made from (this process's selection and drawn piece, each with its
  // MTime); a render where no process's inputs changed reuses it.
  vtkSmartPointer<vtkIdTypeArray> ExchangedSelection;
  struct ExchangeInputs
  {
    const void* selected = nullptr;
    vtkMTimeType selectedTime = 0;
    const void* piece = nullptr;
    vtkMTimeType pieceTime = 0;
    bool operator!=(const ExchangeInputs& o) const
    {
      return selected != o.selected || selectedTime != o.selectedTime || piece != o.piece ||
        pieceTime != o.pieceTime;
    }
  } ExchangedFrom;

private:
  vtkRayTracedSpheresRepresentation(const vtkRayTracedSpheresRepresentation&) = delete;
  void operator=(const vtkRayTracedSpheresRepresentation&) = delete;
};

#endif
