/**
 * @class   vtkSPHBoundaryParticles
 * @brief   The particles of a fluid that lie in its boundary cells (Zirr and Dachsbacher
 *          2015, section 3.1): those of full inner cells of a uniform grid are dropped.
 *
 * Every point of the input vtkPointSet is a sphere of radius r_i = ScaleFactor *
 * (ScaleArray, else Radius). A uniform grid of cells of size CellSize (0: twice the
 * largest radius; at least the largest radius) sorts the spheres; a cell is full when its box
 * is proven covered by the spheres of its 3 x 3 x 3 block of cells, inner when it and its 26
 * neighbours are full (kernel FluidCells.h, the test vtkSPHFluidMapper culls with). The output
 * vtkPolyData holds the points of the other cells, in input order, with all their point data
 * and one vertex each; its field data holds CellSize, OccupiedCells, FullCells, InnerCells and
 * CulledParticles.
 *
 * The fluid's surfaces lie in the boundary cells, so this is the part of a large fluid that a
 * surface extraction or a glyph rendering of its surface needs. The full cells' interior is
 * not represented by the output: vtkSPHFluidMapper (BoundaryCulling) culls by itself and fills
 * the full cells, so give it the whole fluid, not this output (its translucency would miss the
 * interior).
 *
 * Bad input (numeric properties as in vtkRayMapperSetGet.h): points with NaN/Inf
 * coordinates and radii that are NaN, infinite, zero, negative or above 1e15 are
 * dropped with one warning; a missing radius array falls back to Radius with a warning; an
 * empty input gives an empty output with a warning.
 */
#ifndef vtkSPHBoundaryParticles_h
#define vtkSPHBoundaryParticles_h

#include "RayMappersFiltersModule.h" // for export macro
#include "vtkRayMapperSetGet.h" // for vtkRayMapperSetClampMacro
#include "vtkPolyDataAlgorithm.h"

class RAYMAPPERSFILTERS_EXPORT vtkSPHBoundaryParticles : public vtkPolyDataAlgorithm
{
public:
  static vtkSPHBoundaryParticles* New();
  vtkTypeMacro(vtkSPHBoundaryParticles, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** Constant particle radius (1), its point array, a factor on either (1). */
  vtkRayMapperSetClampMacro(Radius, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(Radius, double);
  vtkRayMapperScaleMacro();
  ///@}

  /** @deprecated RadiusArrayName and RadiusScale (vtkRayMapperDeprecatedRadiusNamesMacro). */
  vtkRayMapperDeprecatedRadiusNamesMacro();

  ///@{
  /** The culling grid's cell size in world units (0: twice the largest radius). */
  vtkRayMapperSetClampMacro(CellSize, double, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  vtkGetMacro(CellSize, double);
  ///@}

protected:
  vtkSPHBoundaryParticles();
  ~vtkSPHBoundaryParticles() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double Radius = 1.0;
  char* ScaleArray = nullptr;
  double ScaleFactor = 1.0;
  double CellSize = 0.0;

private:
  vtkSPHBoundaryParticles(const vtkSPHBoundaryParticles&) = delete;
  void operator=(const vtkSPHBoundaryParticles&) = delete;
};

#endif
