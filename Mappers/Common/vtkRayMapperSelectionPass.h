// A mapper's part in VTK's hardware selection (vtkHardwareSelector): during a selection render
// the renderer's selector is set and each pass asks every prop for one number per pixel,
// written as an 8-bit RGB colour (red the low byte) that the selector reads back:
//   ACTOR_PASS, PROCESS_PASS, COMPOSITE_INDEX_PASS: the selector's prop colour value
//     (vtkHardwareSelector::GetPropColorValue, set by BeginRenderProp and
//     RenderCompositeIndex: prop id + 1, process id + 1, composite index 1);
//   POINT_ID_LOW24 / CELL_ID_LOW24: the low 24 bits of the attribute id (no offset: the actor
//     pass tells a hit from the background);
//   POINT_ID_HIGH24 / CELL_ID_HIGH24: bits 24 to 31 in red (the selector runs them only when
//     a prop reported, by UpdateMaximumPointId/CellId, an id of 2^24 or more).
// This is the protocol of VTK 9.2's vtkOpenGLPolyDataMapper::ReplaceShaderPicking, so a
// ray-traced prop is selected exactly as an OpenGL one: the selector turns the pixels into
// (process, prop, id) triples, ParaView into a selection of the representation's input.
#ifndef vtkRayMapperSelectionPass_h
#define vtkRayMapperSelectionPass_h

#include "Mappers/Common/Frame.h"

#include "vtkType.h"

class vtkHardwareSelector;
class vtkIdTypeArray;
class vtkRenderer;
class vtkUnsignedIntArray;

namespace vtkRayMapperSelectionPass
{
/// The selector of a selection render, null in an ordinary render.
vtkHardwareSelector* Of(vtkRenderer* ren);

/// Whether the selector asks for point ids (Select Points On) rather than cell ids.
bool SelectsPoints(vtkHardwareSelector* selector);

/// Starts the prop's part of the current pass: BeginRenderProp (the prop colour value),
/// composite index 1, and `maximumId` (the largest id the prop can write) for the selector's
/// decision to run the high-24-bit passes.
void Begin(vtkHardwareSelector* selector, vtkIdType maximumId);
/// Ends it (EndRenderProp).
void End(vtkHardwareSelector* selector);

/// What the ids of the drawn data stand for when it is not the input itself (a process's
/// share of redistributed particles): each element's id in its process's input and that
/// process, the arrays VTK's mappers name PointIdArrayName and ProcessIdArrayName
/// (ParaView's "vtkOriginalPointIds" and "vtkProcessId"); null: the drawn ids themselves and
/// the selector's process.
struct Origins
{
  vtkIdTypeArray* ids = nullptr;
  vtkUnsignedIntArray* processes = nullptr;
};

/// The colours of the current pass for `picks` (id + 1 per pixel, 0: nothing) into `frame`
/// (resized to the picks): opaque where something was hit, with the picks' depth, empty
/// (alpha 0: not drawn) elsewhere. The id passes write origins.ids[id] and the process pass
/// origins.processes[id] + 1 when given (the process only when the selector takes process
/// ids from the data, as vtkOpenGLPolyDataMapper does).
void Encode(vtkHardwareSelector* selector,
  const raymappers::IdFrame& picks,
  const Origins& origins,
  raymappers::Frame& frame);
}

#endif
