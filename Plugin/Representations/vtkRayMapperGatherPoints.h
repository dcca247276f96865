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

/// The points of `input`; an empty polydata when `input` is null (a process without
/// input: the client, or the render server of a client-server session).
vtkSmartPointer<vtkPolyData> vtkRayMapperGatherPoints(vtkDataObject* input);

/// The point set a particle representation renders from the piece the view delivered: the
/// piece itself when it is a vtkPolyData (the representation's own point set, or the one
/// its parallel exchange made), else its gathered points (an empty point set for no piece:
/// the client of a remote render).
vtkSmartPointer<vtkPolyData> vtkRayMapperDeliveredPoints(vtkDataObject* piece);

/// The largest particle radius: |scale| times the largest value of the point array
/// `radiusArray` (first component) of `points` that gives a radius the mappers draw (in
/// (0, 1e15]: vtkRayMapperPointArrays::LargestParticleLength), or |scale| times `radius`
/// when the array is null or empty; 0 when not finite.
double vtkRayMapperLargestRadius(vtkPolyData* points,
  const char* radiusArray,
  double radius,
  double scale);

/// Hands a particle radius setting to a mapper with SetRadius, SetScaleFactor and
/// SetScaleArray (null: no array; vtkPointGaussianMapper's names) and returns in `radius` and `scale` what the mapper
/// kept (it rejects NaN and clamps).
template<typename MapperType>
void vtkRayMapperPushRadius(MapperType* mapper, double& radius, double& scale, const char* array)
{
  mapper->SetRadius(radius);
  mapper->SetScaleFactor(scale);
  radius = mapper->GetRadius();
  scale = mapper->GetScaleFactor();
  mapper->SetScaleArray(array);
}

#endif
