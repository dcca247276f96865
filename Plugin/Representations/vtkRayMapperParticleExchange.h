/**
 * vtkRayMapperParticleExchange: what the particle representations exchange between
 * rendering processes (see vtkRayMapperPropRepresentation's Distribution). All functions
 * taking a controller are collective: every process calls them with the same cuts.
 */
#ifndef vtkRayMapperParticleExchange_h
#define vtkRayMapperParticleExchange_h

#include "vtkBoundingBox.h"  // for vtkBoundingBox
#include "vtkSmartPointer.h" // for vtkSmartPointer

#include <vector>

class vtkDataSet;
class vtkIdTypeArray;
class vtkMultiProcessController;
class vtkPolyData;

/// The point arrays that name, for each particle of an exchanged piece, its id in the piece
/// of the process that sent it (vtkIdTypeArray) and that process (vtkUnsignedIntArray): what
/// a hardware selection must report, and what the selection's highlight is matched against.
extern const char* const vtkRayMapperOriginIdsName;
extern const char* const vtkRayMapperOriginProcessesName;

/// `local` (a shallow copy) with its particles' origins: ids 0..n-1 and process `rank`.
vtkSmartPointer<vtkPolyData> vtkRayMapperTagOrigins(vtkPolyData* local, int rank);

/// The ids, in the exchanged `piece` this process renders, of the particles that some
/// process selected: every process's `own` selection (ids in its own piece, may be null) is
/// shared with all, and matched against the piece's origin arrays. Collective.
vtkSmartPointer<vtkIdTypeArray> vtkRayMapperSelectedOfExchange(vtkIdTypeArray* own,
  vtkDataSet* piece,
  vtkMultiProcessController* controller);

/// The region process `rank` renders: its cut, with the faces that lie on the boundary of
/// the union of all cuts moved to +-VTK_DOUBLE_MAX (particles reach beyond the cuts, which
/// only bound the particles' centres; only the faces between cuts order the images).
void vtkRayMapperRegionOf(const std::vector<vtkBoundingBox>& cuts, int rank, double bounds[6]);

/// The particles this process renders in its region, from every process's `local` ones:
/// those whose support sphere (radius `margin`) meets the region, its own and the ghosts
/// of the neighbours (the view leaves particle data where it is; this moves it).
/// Point arrays: those all processes share. `ghosts` receives the number of particles
/// received whose centre lies outside the region.
vtkSmartPointer<vtkPolyData> vtkRayMapperDistributeParticles(vtkPolyData* local,
  const std::vector<vtkBoundingBox>& cuts,
  double margin,
  vtkMultiProcessController* controller,
  long long& ghosts);

/// All processes' particles on process 0 (in rank order), an empty point set elsewhere.
vtkSmartPointer<vtkPolyData> vtkRayMapperGatherParticlesToFirst(vtkPolyData* local,
  vtkMultiProcessController* controller);

#endif
