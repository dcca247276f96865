/**
 * @class   vtkZSweepVolumeRepresentation
 * @brief   ParaView representation "Z-Sweep Volume": exact volume rendering of the cells
 *          of a grid by vtkZSweepVolumeMapper, without tetrahedralizing it.
 *
 * The input (an unstructured or structured grid, or a composite of them such as an Exodus
 * or PLOT3D reader's output) is gathered into one vtkUnstructuredGrid that keeps its
 * hexahedra, wedges and pyramids (structured grids give hexahedra, image data voxels), and
 * rendered with the color array's color map (LookupTable) and opacity map
 * (ScalarOpacityFunction) over ScalarOpacityUnitDistance, point or cell data.
 *
 * The classification (the maps and the unit distance) is vtkRayMapperVolumeClassification,
 * shared with the particle volumes.
 *
 * Its own properties: the integrator (exact, the dissertation's formula, midpoint), the
 * tile size, the list threshold K and the early-termination opacity. The mapper's
 * statistics of the last render are an information property (ZSweepRenderStatistics).
 */

#ifndef vtkZSweepVolumeRepresentation_h
#define vtkZSweepVolumeRepresentation_h

#include "RayMappersRepresentationsModule.h" // for export macro
#include "vtkRayMapperPropRepresentation.h"
#include "vtkSmartPointer.h" // for vtkSmartPointer

#include <memory> // for std::unique_ptr

class vtkDataSet;
class vtkPiecewiseFunction;
class vtkRayMapperVolumeClassification;
class vtkScalarsToColors;
class vtkUnstructuredGrid;
class vtkVolume;
class vtkZSweepVolumeMapper;

class RAYMAPPERSREPRESENTATIONS_EXPORT vtkZSweepVolumeRepresentation : public vtkRayMapperPropRepresentation
{
public:
  static vtkZSweepVolumeRepresentation* New();
  vtkTypeMacro(vtkZSweepVolumeRepresentation, vtkRayMapperPropRepresentation);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  //***************************************************************************
  // Classification.
  void SetLookupTable(vtkScalarsToColors* lut);
  void SetScalarOpacity(vtkPiecewiseFunction* opacity);
  void SetScalarOpacityUnitDistance(double distance);

  //***************************************************************************
  // Forwarded to vtkZSweepVolumeMapper (see there).
  void SetIntegrator(int integrator);
  void SetCellField(int field);
  void SetCurvedTolerance(double tolerance);
  void SetTileSize(int size);
  void SetListThreshold(int k);
  void SetSparsification(bool on);
  void SetTerminationOpacity(double opacity);
  void SetSubsampling(int p);
  void SetFrameBudget(double seconds);
  /** The mapper's NumberOfThreads (its own TBB task arena; 0: the default). */
  void SetNumberOfThreads(int threads);

  vtkZSweepVolumeMapper* GetMapper();
  vtkVolume* GetVolume();

protected:
  vtkZSweepVolumeRepresentation();
  ~vtkZSweepVolumeRepresentation() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  vtkDataSet* GetProcessedData() override;
  void SetDeliveredPiece(vtkDataObject* piece) override;
  bool GetLastFrame(double frame[2]) override;
  void SetLastFrame(const double frame[2]) override;
  Distribution GetDistribution() override { return Distribution::Cells; }

  /**
   * Selects the color array (point or cell data) on the mapper and hands the color and
   * opacity maps to the volume property.
   */
  void UpdateClassification();

  vtkSmartPointer<vtkVolume> Volume;
  vtkSmartPointer<vtkZSweepVolumeMapper> Mapper;
  vtkSmartPointer<vtkUnstructuredGrid> ProcessedData;
  std::unique_ptr<vtkRayMapperVolumeClassification> Classification;

private:
  vtkZSweepVolumeRepresentation(const vtkZSweepVolumeRepresentation&) = delete;
  void operator=(const vtkZSweepVolumeRepresentation&) = delete;
};

#endif
