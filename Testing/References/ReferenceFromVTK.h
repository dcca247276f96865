// The reference scene read from VTK objects (for the C++ rendering tests): the camera's
// world-to-NDC matrix, the renderer's lights, the transfer functions of a volume property
// sampled finely over the union of its functions' ranges (VTK's functions clamp outside
// their nodes, so the table does too), and the material of an actor's property.
#ifndef RayMappers_Reference_ReferenceFromVTK_h
#define RayMappers_Reference_ReferenceFromVTK_h

#include "ReferenceScene.h"

class vtkProperty;
class vtkRenderer;
class vtkVolumeProperty;

namespace raymappers::reference
{

/// The renderer's active camera for its viewport (after a render, so the clipping range
/// and the aspect are those of the frame).
ReferenceCamera cameraOf(vtkRenderer* renderer);

/// The renderer's switched-on lights (directional only: a positional light throws
/// std::runtime_error), their directions as VTK transforms them for the current camera.
std::vector<ReferenceLight> lightsOf(vtkRenderer* renderer);

ReferenceTransferFunction transferFunctionOf(vtkVolumeProperty* property, int samples = 8192);

ReferenceMaterial materialOf(vtkProperty* property);

}

#endif
