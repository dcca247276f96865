/**
 * vtkRayMapperGatherPoints: the points that the particle representations draw.
 *
 * Gathers all the points of a dataset, or of all the leaves of a composite dataset,
 * into one vtkPolyData without cells, with the point arrays that all the leaves share.
 * Points that a ghost array marks as duplicate or hidden are dropped (in parallel their
 * owner draws them). One point set without such ghosts is shared, not copied.
 */
#ifndef vtkRayMapperGatherPoints_h
#define vtkRayMapperGatherPoints_h

#include "vtkSmartPointer.h" // for vtkSmartPointer

class vtkDataObject;
class vtkPolyData;

vtkSmartPointer<vtkPolyData> vtkRayMapperGatherPoints(vtkDataObject* input);

#endif
