/**
 * @class   vtkRayMapperPropRepresentation
 * @brief   What the RayMappers representations share: one vtkProp3D (an actor or a volume)
 *          in the render view, its visibility and transform, and an optional input of any
 *          dataset or composite dataset.
 *
 * Subclasses create their prop and mapper and hand the prop to SetProp() in their
 * constructor, gather their input into one dataset in RequestData (GetProcessedData()),
 * and take the piece the view delivers to their process in SetDeliveredPiece(). This class
 * answers the view's requests: on REQUEST_UPDATE it hands the processed data and its bounds
 * (grown by GetBoundsMargin(), for glyphs and kernels that reach beyond the points) to the
 * view; on REQUEST_RENDER it passes the delivered piece to the subclass.
 *
 * With several rendering processes (pvbatch or pvserver under mpirun, IceT compositing)
 * the subclass's GetDistribution() says how its data take part:
 * - Local: opaque geometry with depth; every process draws its own piece and IceT keeps
 *   the nearest fragment.
 * - Surfaces: opaque particle glyphs (the spheres). Alone in the view, as Local. When the
 *   view partitions space (a volume or other translucent data in the view: IceT then
 *   blends the processes' images in the boxes' visibility order, without depth), as
 *   Particles: every process receives the glyphs reaching into its box and draws only the
 *   surface inside it, so that a glyph another process holds, or one cut by a box face,
 *   lands in the right place of the blend.
 * - Particles: a particle volume. The view partitions space into one box per process
 *   (ParaView's kd-tree cuts, balanced on the particles); every process then receives the
 *   particles whose support (GetGhostMargin(), the largest over all processes) reaches
 *   into its box, its own and the neighbours' ghosts, and renders only inside its box
 *   (SetRegion), so that the boxes' images, blended front to back in visibility order
 *   (ordered compositing), are the one-process image.
 * - Cells: a volume of cells; the view redistributes the cells into the boxes, splitting
 *   the cells on box faces (ParaView's own unstructured-grid volumes do the same), and
 *   blends the boxes' images in order.
 * - GatherToFirst: nothing of it can be split (refraction and screen-space effects see the
 *   whole fluid): all particles are gathered to the first process, which alone renders
 *   them; the others' images are empty, so ordered blending leaves its image unchanged.
 *   Exact, but not parallel; the representation says so once.
 */

#ifndef vtkRayMapperPropRepresentation_h
#define vtkRayMapperPropRepresentation_h

#include "RayMappersRepresentationsModule.h" // for export macro
#include "vtkPVDataRepresentation.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

#include <vector> // for std::vector

class vtkAbstractVolumeMapper;
class vtkDataSet;
class vtkProp3D;
class vtkRayMapperStatistics;
class vtkVolume;

class RAYMAPPERSREPRESENTATIONS_EXPORT vtkRayMapperPropRepresentation
  : public vtkPVDataRepresentation
{
public:
  vtkTypeMacro(vtkRayMapperPropRepresentation, vtkPVDataRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Data delivery and rendering passes of the view (see vtkPVDataRepresentation).
   */
  int ProcessViewRequest(vtkInformationRequestKey* request_type,
    vtkInformation* inInfo,
    vtkInformation* outInfo) override;

  /**
   * The data that is rendered (after RequestData), else the input.
   */
  vtkDataObject* GetRenderedDataObject(int port) override;

  /**
   * Shows or hides the prop.
   */
  void SetVisibility(bool val) override;

  //***************************************************************************
  // Forwarded to the prop.
  virtual void SetOrientation(double, double, double);
  virtual void SetOrigin(double, double, double);
  virtual void SetPickable(int val);
  virtual void SetPosition(double, double, double);
  virtual void SetScale(double, double, double);
  virtual void SetUserTransform(const double matrix[16]);

  /**
   * The mapper's statistics of the last render (phases, counters, effects), one
   * "kind name value" per line.
   */
  const char* GetRenderStatistics();

protected:
  vtkRayMapperPropRepresentation();
  ~vtkRayMapperPropRepresentation() override;

  /**
   * The prop this representation adds to the view; `selectable`: whether ParaView's
   * hardware selection may pick it.
   */
  void SetProp(vtkProp3D* prop, bool selectable);

  /**
   * A new vtkVolume, drawn by `mapper` with a new vtkVolumeProperty, made this
   * representation's prop (not selectable: ParaView's hardware selection picks no volumes);
   * `mapper`'s warnings reach the output window only while this representation is shown.
   */
  vtkSmartPointer<vtkVolume> SetVolumeProp(vtkAbstractVolumeMapper* mapper);

  /**
   * The statistics object of the mapper, which GetRenderStatistics() reports.
   */
  vtkSmartPointer<vtkRayMapperStatistics> Statistics;

  bool AddToView(vtkView* view) override;
  bool RemoveFromView(vtkView* view) override;

  /**
   * Any dataset or composite dataset, optional (representations have no input on the client
   * and on the render server of a client-server session).
   */
  int FillInputPortInformation(int port, vtkInformation* info) override;

  /**
   * The dataset RequestData made from the input (null before it ran).
   */
  virtual vtkDataSet* GetProcessedData() = 0;

  /**
   * How far the rendered geometry reaches beyond the processed data's points (default 0).
   */
  virtual double GetBoundsMargin() { return 0.0; }

  /**
   * How far beyond its box a process needs the others' particles (Particles and Surfaces
   * distributions; default GetBoundsMargin(): those whose geometry reaches in; more for
   * rays that leave the box, VTK_DOUBLE_MAX for all of them).
   */
  virtual double GetGhostMargin() { return this->GetBoundsMargin(); }

  /**
   * The largest GetBoundsMargin() of all processes, set by the last exchange between them
   * (the particles' largest reach over the whole data); -1 without one.
   */
  double GlobalBoundsMargin = -1.0;

  /**
   * The piece the view delivered to this process for rendering; null when nothing was
   * delivered (e.g. the client when rendering remotely).
   */
  virtual void SetDeliveredPiece(vtkDataObject* piece) = 0;

  /**
   * How several rendering processes share this representation's data (see above).
   */
  enum class Distribution
  {
    Local,
    Surfaces,
    Particles,
    Cells,
    GatherToFirst
  };
  virtual Distribution GetDistribution() { return Distribution::Local; }

  /**
   * The last frame of the mapper's time-critical loop, {seconds, sample distance}
   * (vtkRayMapperSampleDistanceMacro): false for a mapper without one. With several
   * rendering processes, each render first gives all of them the slowest one's, so that
   * they draw an interactive frame at one sample distance (no seams between their parts).
   */
  virtual bool GetLastFrame(double vtkNotUsed(frame)[2]) { return false; }
  virtual void SetLastFrame(const double vtkNotUsed(frame)[2]) {}

  /**
   * The box (xmin, xmax, ymin, ymax, zmin, zmax) this process renders in (Particles and
   * Surfaces distributions); +-VTK_DOUBLE_MAX on unbounded sides, all of space with one
   * process or no partition.
   */
  virtual void SetRegion(const double bounds[6]) {}

  /**
   * The warnings and errors of `source` (this representation, its mapper) reach VTK's
   * output window only while this representation is shown. ParaView's composite
   * representation hands every property, and the defaults its domains compute from the data,
   * to all of its sub-representations: a value that several share (Ambient,
   * ScalarOpacityUnitDistance, a bounds-based radius of a data set with an infinite
   * coordinate) would otherwise be warned about once by each, shown or not. The values are
   * checked (rejected or clamped) all the same.
   */
  void WarnOnlyWhenShown(vtkObject* source);

  vtkSmartPointer<vtkProp3D> Prop;
  bool Selectable = false;
  // Whether the last delivered piece has points: the prop is shown only then.
  bool HasPiece = false;
  // Whether the last piece came from an exchange between processes (the same on all of
  // them); a Selectable one carries its particles' origins (vtkRayMapperTagOrigins).
  bool PieceExchanged = false;

private:
  /// Adds the prop to the renderer of `view` (and to its hardware selection when the prop is
  /// selectable), or removes it; false when `view` is no render view or there is no prop.
  bool PlaceProp(vtkView* view, bool add);

  /// With several rendering processes: every one's mapper gets the slowest one's last
  /// frame (GetLastFrame). Collective.
  void ShareLastFrame();

  /// The piece to render in parallel runs: the delivered particles with their ghosts
  /// (Particles) or all particles on the first process (GatherToFirst). Collective.
  vtkDataObject* DistributedPiece(vtkDataObject* delivered);

  // The last exchange, redone only when the delivered piece, the cuts or the margin change.
  vtkSmartPointer<vtkDataObject> ExchangedPiece;
  vtkDataObject* ExchangedFrom = nullptr;
  vtkMTimeType ExchangedFromTime = 0;
  vtkMTimeType ExchangedCutsTime = 0;
  double ExchangedMargin = -1.0;
  bool WarnedGathered = false;
  vtkMTimeType WarnedEmptyInputTime = 0;
  struct Forwarding;
  std::vector<Forwarding> Forwardings;

  vtkRayMapperPropRepresentation(const vtkRayMapperPropRepresentation&) = delete;
  void operator=(const vtkRayMapperPropRepresentation&) = delete;
};

#endif
