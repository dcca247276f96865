/**
 * @class   vtkRayMapperPropRepresentation
 * @brief   What the RayMappers representations share: one vtkProp3D (an actor or a volume)
 *          in the render view, its visibility and transform, and an optional input of any
 *          dataset or composite dataset.
 *
 * Subclasses create their prop and mapper and hand the prop to SetProp() in their
 * constructor; they gather their input in RequestData and deliver it in ProcessViewRequest.
 */

#ifndef vtkRayMapperPropRepresentation_h
#define vtkRayMapperPropRepresentation_h

#include "RayMappersRepresentationsModule.h" // for export macro
#include "vtkPVDataRepresentation.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

class vtkProp3D;

class RAYMAPPERSREPRESENTATIONS_EXPORT vtkRayMapperPropRepresentation
  : public vtkPVDataRepresentation
{
public:
  vtkTypeMacro(vtkRayMapperPropRepresentation, vtkPVDataRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

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

  vtkSmartPointer<vtkProp3D> Prop;
  bool Selectable = false;

private:
  vtkRayMapperPropRepresentation(const vtkRayMapperPropRepresentation&) = delete;
  void operator=(const vtkRayMapperPropRepresentation&) = delete;
};

#endif
