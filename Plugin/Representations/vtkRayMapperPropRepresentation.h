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
 */

#ifndef vtkRayMapperPropRepresentation_h
#define vtkRayMapperPropRepresentation_h

#include "RayMappersRepresentationsModule.h" // for export macro
#include "vtkPVDataRepresentation.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

class vtkDataSet;
class vtkProp3D;

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

protected:
  vtkRayMapperPropRepresentation();
  ~vtkRayMapperPropRepresentation() override;

  /**
   * The prop this representation adds to the view; `selectable`: whether ParaView's
   * hardware selection may pick it.
   */
  void SetProp(vtkProp3D* prop, bool selectable);

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
   * The piece the view delivered to this process for rendering; null when nothing was
   * delivered (e.g. the client when rendering remotely).
   */
  virtual void SetDeliveredPiece(vtkDataObject* piece) = 0;

  vtkSmartPointer<vtkProp3D> Prop;
  bool Selectable = false;

private:
  vtkRayMapperPropRepresentation(const vtkRayMapperPropRepresentation&) = delete;
  void operator=(const vtkRayMapperPropRepresentation&) = delete;
};

#endif
