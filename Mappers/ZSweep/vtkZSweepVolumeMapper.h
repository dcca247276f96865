/**
 * @class   vtkZSweepVolumeMapper
 * @brief   Exact volume rendering of unstructured grids by a sweep plane (Farias's ZSweep),
 *          in parallel screen tiles, with native hexahedra, wedges and pyramids.
 *
 * Renders the tetrahedra, hexahedra, voxels, wedges and pyramids of a
 * vtkUnstructuredGridBase, mixed in one grid, without tetrahedralizing it, with the
 * vtkVolumeProperty of the vtkVolume (component 0's color and scalar opacity functions and
 * its ScalarOpacityUnitDistance). The scalar is chosen as for every VTK volume mapper
 * (ScalarMode, SelectScalarArray; component 0): point data varies linearly along a ray
 * inside a cell (exact for tetrahedra; for the other cells, between the triangles of their
 * faces, each quad split along the diagonal through its smallest point id), cell data is
 * constant in a cell.
 *
 * The method (Farias 2001, chapters 4 and 5): the faces are swept in depth order of their
 * nearest vertex, scan converted exactly into per-pixel lists, and composited in delayed
 * stages (a z-target and a list-size threshold K that doubles when needed), in screen
 * tiles in parallel. The mapper keeps the last render's depth order of the faces and starts
 * the next render's sort from it, so a render from the same camera (a new transfer
 * function, say) only checks the order (counters order_moves, order_sorts).
 * Integrator EXACT (default) integrates the emission-absorption model
 * exactly for transfer functions that are piecewise linear in extinction and color between
 * their nodes; FARIAS uses the dissertation's second-order closed form; MIDPOINT a constant
 * segment. Details in Mappers/ZSweep/ZSweepRenderer.h and OpticalModel.h.
 * Inside hexahedra, wedges and pyramids with point data, CellField NATIVE (default) uses
 * the cell's own interpolation (trilinear in a hexahedron), cut along each ray into pieces
 * linear to CurvedTolerance of the scalar range; SPLIT_FACES the linear field between the
 * crossings of the triangles its faces are split into (as a tetrahedralization would give).
 * The cells' bounds are their split faces in both (Mappers/ZSweep/IsoparametricCell.h).
 *
 * Opaque geometry drawn before the volume stops the rays (the depth buffer is read only when
 * the renderer holds some: effect opaque_depth). Cells with a bad point index, a
 * non-finite point or scalar, or zero volume (flat to the precision of their points'
 * coordinates, float or double, or at most 1e-12 of the cube of their bounding box's
 * diagonal), and cells of other types (quadratic cells, polyhedra, prisms of more
 * sides, cells below 3D) are skipped with one warning each kind (the skipped types named
 * with their counts); an empty grid warns once.
 * Numeric properties reject NaN and infinity and clamp out-of-range values, each with one
 * warning (vtkRayMapperSetGet.h; lengths up to 1e15); an array of several components read
 * as a scalar gives its first component (one warning when they differ); a degenerate camera
 * (the eye at the focal point, a NaN position) gives one warning and nothing drawn. Inverted cells (vertices in mirrored
 * order) are drawn as they are, without a warning: each cell's sides come from the sign of
 * its volume (counter inverted_cells).
 *
 * GetStatistics() reports the phases, counters and effects of the last render.
 */
#ifndef vtkZSweepVolumeMapper_h
#define vtkZSweepVolumeMapper_h

#include "RayMappersMappersModule.h" // for export macro
#include "vtkRayMapperSetGet.h" // for vtkRayMapperSetClampMacro
#include "vtkUnstructuredGridVolumeMapper.h"

#include <memory> // for std::unique_ptr

class vtkRayMapperStatistics;
namespace raymappers
{
struct ZSweepParameters;
}

#define VTK_ZSWEEP_INTEGRATOR_EXACT 0
#define VTK_ZSWEEP_INTEGRATOR_FARIAS 1
#define VTK_ZSWEEP_INTEGRATOR_MIDPOINT 2

#define VTK_ZSWEEP_CELL_FIELD_NATIVE 0
#define VTK_ZSWEEP_CELL_FIELD_SPLIT_FACES 1

class RAYMAPPERSMAPPERS_EXPORT vtkZSweepVolumeMapper : public vtkUnstructuredGridVolumeMapper
{
public:
  static vtkZSweepVolumeMapper* New();
  vtkTypeMacro(vtkZSweepVolumeMapper, vtkUnstructuredGridVolumeMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * How a segment between two face crossings is integrated: EXACT (default), FARIAS (the
   * dissertation's second-order formula) or MIDPOINT. Cell data always uses the exact
   * homogeneous formula.
   */
  vtkRayMapperSetClampMacro(Integrator, int, VTK_ZSWEEP_INTEGRATOR_EXACT, VTK_ZSWEEP_INTEGRATOR_MIDPOINT);
  vtkGetMacro(Integrator, int);
  ///@}

  ///@{
  /**
   * The field inside hexahedra, wedges and pyramids with point data: NATIVE (default), the
   * cell's own interpolation (trilinear in a hexahedron; the mesh then keeps these cells'
   * vertex ids, 33 bytes each and 4 per cell), or SPLIT_FACES, linear between the split
   * faces' crossings.
   */
  vtkRayMapperSetClampMacro(
    CellField, int, VTK_ZSWEEP_CELL_FIELD_NATIVE, VTK_ZSWEEP_CELL_FIELD_SPLIT_FACES);
  vtkGetMacro(CellField, int);
  void SetCellFieldToNative() { this->SetCellField(VTK_ZSWEEP_CELL_FIELD_NATIVE); }
  void SetCellFieldToSplitFaces() { this->SetCellField(VTK_ZSWEEP_CELL_FIELD_SPLIT_FACES); }
  ///@}

  ///@{
  /**
   * With CellField NATIVE: the largest departure of the field's linear pieces from the
   * field along a ray, as a fraction of the scalar range (1e-8 to 0.1, default 1e-4; the
   * pieces grow like its inverse square root).
   */
  vtkRayMapperSetClampMacro(CurvedTolerance, double, 1e-8, 0.1);
  vtkGetMacro(CurvedTolerance, double);
  ///@}

  ///@{
  /**
   * Side of the screen tiles swept in parallel (8 to 1024, default 32: smaller tiles keep
   * a tile's pixel lists in cache; 32 swept 5-15 % faster than 64 on the benchmarks).
   */
  vtkRayMapperSetClampMacro(TileSize, int, 8, 1024);
  vtkGetMacro(TileSize, int);
  ///@}

  ///@{
  /**
   * The list-size threshold K of delayed compositing (2 to 4096, default 16).
   */
  vtkRayMapperSetClampMacro(ListThreshold, int, 2, 4096);
  vtkGetMacro(ListThreshold, int);
  ///@}

  ///@{
  /**
   * A pixel stops once its opacity reaches this (default 1: never early, exact).
   */
  vtkRayMapperSetClampMacro(TerminationOpacity, double, 0.0, 1.0);
  vtkGetMacro(TerminationOpacity, double);
  ///@}

  ///@{
  /**
   * Time-critical rendering (Farias 2001, chapter 3) with the names of VTK's
   * vtkUnstructuredGridVolumeZSweepMapper: rays ImageSampleDistance d pixels apart, the
   * image enlarged. AutoAdjustSampleDistances (default on): interactive renders choose d
   * from the last frame's time against FrameBudget within [MinimumImageSampleDistance 1,
   * MaximumImageSampleDistance 9]; still renders give the exact image (d = the minimum).
   * See vtkRayMapperSampleDistanceMacro (vtkRayMapperSetGet.h).
   */
  vtkRayMapperSampleDistanceMacro();
  ///@}

  ///@{
  /** @deprecated Subsampling p (0: AutoAdjustSampleDistances; 1 to 9: ImageSampleDistance p
   * with AutoAdjustSampleDistances off), kept for one release. */
  vtkRayMapperDeprecatedSubsamplingMacro(9);
  ///@}

  ///@{
  /**
   * Sparsification (Farias 2001, section 4.3.5): the mesh stores its faces through a subset
   * of the cells that contains every face (a greedy maximal independent set of the dual
   * graph dropped; about 55% of a tetrahedral grid's cells kept) instead of as a list of
   * triangles, and decodes them every frame. Same image; the mesh holds about 40% less
   * memory between frames (tetrahedra; 60% for hexahedra), its build and every frame take
   * a little longer (counters mesh_bytes, kept_cells; phase decode). Default off.
   */
  vtkSetMacro(Sparsification, bool);
  vtkGetMacro(Sparsification, bool);
  vtkBooleanMacro(Sparsification, bool);
  ///@}

  /**
   * Statistics of the last render (counter image_sample_distance_percent: 100 d; the
   * deprecated counter "subsampling": d rounded up).
   */
  vtkRayMapperStatistics* GetStatistics();

  /// The input's bounds; for an input without cells (which the renderer culls before it
  /// renders) also one warning per input change.
  double* GetBounds() VTK_SIZEHINT(6) override;
  void GetBounds(double bounds[6]) override { this->vtkAbstractMapper3D::GetBounds(bounds); }

  ///@{
  /** NumberOfThreads (vtkRayMapperNumberOfThreadsMacro, vtkRayMapperSetGet.h). */
  vtkRayMapperNumberOfThreadsMacro();
  ///@}

  void Render(vtkRenderer* ren, vtkVolume* vol) override;
  void ReleaseGraphicsResources(vtkWindow* win) override;

protected:
  vtkZSweepVolumeMapper();
  ~vtkZSweepVolumeMapper() override;

  int Integrator = VTK_ZSWEEP_INTEGRATOR_EXACT;
  int CellField = VTK_ZSWEEP_CELL_FIELD_NATIVE;
  double CurvedTolerance = 1e-4;
  int TileSize = 32;
  int ListThreshold = 16;
  double TerminationOpacity = 1.0;
  double ImageSampleDistance = 1.0;
  vtkTypeBool AutoAdjustSampleDistances = 1;
  double MinimumImageSampleDistance = 1.0;
  double MaximumImageSampleDistance = 9.0;
  double FrameBudget = 0.0;
  bool Sparsification = false;

  int NumberOfThreads = 0;

private:
  vtkZSweepVolumeMapper(const vtkZSweepVolumeMapper&) = delete;
  void operator=(const vtkZSweepVolumeMapper&) = delete;

  /// Rebuilds the mesh when the input, the scalar selection, the scalars or Sparsification
  /// changed.
  /// Returns false (with an error) when there is no scalar to render.
  bool UpdateMesh(vtkUnstructuredGridBase* input);
  /// The kernel's parameters from the properties.
  raymappers::ZSweepParameters GatherParameters() const;

  /// One render, in the mapper's task arena (Render runs it there).
  void RenderFrame(vtkRenderer* ren, vtkVolume* vol);

  struct Internals;
  std::unique_ptr<Internals> Impl;
};

#endif
