#include "BenchData.h"

#include "vtkAppendFilter.h"
#include "vtkCellArray.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkExodusIIReader.h"
#include "vtkGenericDataObjectReader.h"
#include "vtkLAMMPSDumpReader.h"
#include "vtkMultiBlockPLOT3DReader.h"
#include "vtkPDBReader.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnstructuredGrid.h"
#include "vtkXMLGenericDataObjectReader.h"
#include "vtksys/SystemTools.hxx"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numeric>

namespace bench
{

namespace
{
bool EndsWith(const std::string& s, const std::string& tail)
{
  return s.size() >= tail.size() &&
         std::equal(tail.rbegin(),
           tail.rend(),
           s.rbegin(),
           [](char a, char b) { return std::tolower(a) == std::tolower(b); });
}
}

std::string BaseName(const std::string& path)
{
  return vtksys::SystemTools::GetFilenameWithoutLastExtension(
    vtksys::SystemTools::GetFilenameName(path));
}

vtkSmartPointer<vtkDataObject> ReadAny(const std::string& path)
{
  if (!vtksys::SystemTools::FileExists(path, true))
  {
    std::cerr << "raymappers: no such file: " << path << "\n";
    return nullptr;
  }
  if (EndsWith(path, ".pdb"))
  {
    vtkNew<vtkPDBReader> r;
    r->SetFileName(path.c_str());
    r->Update();
    return r->GetOutputDataObject(0);
  }
  if (EndsWith(path, ".ex2") || EndsWith(path, ".exo") || EndsWith(path, ".e") ||
      EndsWith(path, ".g"))
  {
    vtkNew<vtkExodusIIReader> r;
    r->SetFileName(path.c_str());
    r->UpdateInformation();
    r->SetAllArrayStatus(vtkExodusIIReader::NODAL, 1);
    r->SetAllArrayStatus(vtkExodusIIReader::ELEM_BLOCK, 1);
    r->Update();
    return r->GetOutputDataObject(0);
  }
  if (EndsWith(path, "xyz.bin"))
  {
    // PLOT3D: the solution NAMEq.bin beside the grid NAMExyz.bin, if present.
    std::string q = path.substr(0, path.size() - 7) + "q.bin";
    vtkNew<vtkMultiBlockPLOT3DReader> r;
    r->SetXYZFileName(path.c_str());
    if (vtksys::SystemTools::FileExists(q, true))
    {
      r->SetQFileName(q.c_str());
    }
    r->SetAutoDetectFormat(1);
    r->Update();
    return r->GetOutputDataObject(0);
  }
  if (EndsWith(path, ".dump") || EndsWith(path, ".lammpstrj"))
  {
    vtkNew<vtkLAMMPSDumpReader> r;
    r->SetFileName(path.c_str());
    r->Update();
    return r->GetOutputDataObject(0);
  }
  if (EndsWith(path, ".vtk"))
  {
    vtkNew<vtkGenericDataObjectReader> r;
    r->SetFileName(path.c_str());
    r->ReadAllScalarsOn();
    r->ReadAllVectorsOn();
    r->ReadAllFieldsOn();
    r->Update();
    return r->GetOutput();
  }
  if (EndsWith(path, ".vtp") || EndsWith(path, ".vtu") || EndsWith(path, ".vti") ||
      EndsWith(path, ".vts") || EndsWith(path, ".vtm"))
  {
    vtkNew<vtkXMLGenericDataObjectReader> r;
    r->SetFileName(path.c_str());
    r->Update();
    return r->GetOutput();
  }
  std::cerr << "raymappers: unknown file type (legacy .vtk, VTK XML, Exodus, PDB, PLOT3D "
               "NAMExyz.bin, LAMMPS .dump/.lammpstrj): "
            << path << "\n";
  return nullptr;
}

vtkSmartPointer<vtkPolyData> ToPointCloud(vtkDataObject* data)
{
  auto cloud = vtkSmartPointer<vtkPolyData>::New();
  if (!data)
  {
    return cloud;
  }
  vtkSmartPointer<vtkDataSet> merged;
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(data))
  {
    // vtkAppendFilter keeps the arrays that all blocks share.
    vtkNew<vtkAppendFilter> append;
    append->MergePointsOff();
    vtkSmartPointer<vtkCompositeDataIterator> it;
    it.TakeReference(composite->NewIterator());
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      if (auto* ds = vtkDataSet::SafeDownCast(it->GetCurrentDataObject()))
      {
        append->AddInputData(ds);
      }
    }
    if (append->GetNumberOfInputConnections(0) == 0)
    {
      return cloud;
    }
    append->Update();
    merged = append->GetOutput();
  }
  else
  {
    merged = vtkDataSet::SafeDownCast(data);
  }
  if (!merged)
  {
    return cloud;
  }
  const vtkIdType n = merged->GetNumberOfPoints();
  vtkNew<vtkPoints> points;
  if (auto* ps = vtkPointSet::SafeDownCast(merged))
  {
    points->ShallowCopy(ps->GetPoints());
  }
  else
  {
    points->SetNumberOfPoints(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      points->SetPoint(i, merged->GetPoint(i));
    }
  }
  cloud->SetPoints(points);
  cloud->GetPointData()->ShallowCopy(merged->GetPointData());
  vtkNew<vtkCellArray> verts;
  vtkNew<vtkIdTypeArray> conn;
  conn->SetNumberOfValues(n);
  std::iota(conn->GetPointer(0), conn->GetPointer(0) + n, vtkIdType(0));
  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfValues(n + 1);
  std::iota(offsets->GetPointer(0), offsets->GetPointer(0) + n + 1, vtkIdType(0));
  verts->SetData(offsets, conn);
  cloud->SetVerts(verts);
  return cloud;
}

vtkDataArray* FindRadiusArray(vtkPolyData* points, std::string& name, double& factor)
{
  // A diameter, or an SPH smoothing length h (a support of two radii, the RBF default,
  // then reaches h), gives half its value.
  for (const char* candidate : { "radius", "radii", "r", "Radius", "diameter", "smoothing_length" })
  {
    vtkDataArray* a = points->GetPointData()->GetArray(candidate);
    if (a)
    {
      name = candidate;
      factor = name == "diameter" || name == "smoothing_length" ? 0.5 : 1.0;
      return a;
    }
  }
  return nullptr;
}

vtkDataArray* FindColorArray(vtkPolyData* points)
{
  vtkPointData* pd = points->GetPointData();
  if (pd->GetScalars() && pd->GetScalars()->GetNumberOfComponents() == 1)
  {
    return pd->GetScalars();
  }
  for (const char* candidate : { "type", "atom_type", "Temp", "temperature", "rho", "density" })
  {
    vtkDataArray* a = pd->GetArray(candidate);
    if (a && a->GetNumberOfComponents() == 1)
    {
      return a;
    }
  }
  for (int i = 0; i < pd->GetNumberOfArrays(); ++i)
  {
    vtkDataArray* a = pd->GetArray(i);
    if (a && a->GetNumberOfComponents() == 1)
    {
      return a;
    }
  }
  return nullptr;
}

double DefaultRadius(vtkPolyData* points)
{
  double b[6];
  points->GetBounds(b);
  const vtkIdType n = std::max<vtkIdType>(1, points->GetNumberOfPoints());
  double volume = 1.0;
  int dims = 0;
  for (int i = 0; i < 3; ++i)
  {
    const double e = b[2 * i + 1] - b[2 * i];
    if (e > 0 && std::isfinite(e))
    {
      volume *= e;
      ++dims;
    }
  }
  if (dims == 0)
  {
    return 1.0;
  }
  return 0.5 * std::pow(volume / static_cast<double>(n), 1.0 / dims);
}

}
