#include "BenchData.h"

#include "vtkAppendFilter.h"
#include "vtkCellArray.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkExodusIIReader.h"
#include "vtkFloatArray.h"
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
#include <sstream>

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

ParticleSize ChooseSize(vtkDataSet* points,
  vtkRayMapperParticleSizes::Role role,
  bool acceptOther,
  double perSpacing,
  double override)
{
  ParticleSize size;
  std::ostringstream how;
  if (override > 0)
  {
    size.constant = override;
    how << "constant " << override << " (given)";
  }
  else if (const char* name =
             vtkRayMapperParticleSizes::FindSizeArrayName(points, role, acceptOther, size.scale))
  {
    size.array = name;
    how << "array '" << name << "'";
    if (size.scale != 1.0)
    {
      how << " x " << size.scale;
    }
  }
  else
  {
    vtkRayMapperParticleSizes::SpacingCache cache;
    size.constant = vtkRayMapperParticleSizes::AutomaticLength(points, perSpacing, cache);
    how << "constant " << size.constant << " (automatic: " << perSpacing
        << " x the typical spacing; no size array)";
  }
  size.how = how.str();
  return size;
}

vtkDataArray* FindNamedArray(vtkDataSet* points,
  std::initializer_list<const char*> names,
  int components)
{
  vtkPointData* pd = points->GetPointData();
  for (const char* candidate : names)
  {
    for (int i = 0; i < pd->GetNumberOfArrays(); ++i)
    {
      vtkDataArray* a = pd->GetArray(i);
      const char* name = pd->GetArrayName(i);
      if (a && name && vtksys::SystemTools::Strucmp(name, candidate) == 0 &&
        (components == 0 || a->GetNumberOfComponents() == components))
      {
        return a;
      }
    }
  }
  return nullptr;
}

std::string ListPointArrays(vtkDataSet* points)
{
  vtkPointData* pd = points->GetPointData();
  std::ostringstream list;
  for (int i = 0; i < pd->GetNumberOfArrays(); ++i)
  {
    const char* name = pd->GetArrayName(i);
    list << (i ? ", " : "") << "'" << (name ? name : "") << "' ("
         << pd->GetAbstractArray(i)->GetNumberOfComponents() << ")";
  }
  return pd->GetNumberOfArrays() ? list.str() : std::string("none");
}

vtkDataArray* FindSpeedArray(vtkPolyData* points)
{
  if (vtkDataArray* speed = FindNamedArray(points, { "vmag", "speed", "velocity_magnitude" }, 1))
  {
    return speed;
  }
  vtkDataArray* velocity = FindNamedArray(points, { "v", "vel", "velocity" }, 3);
  if (!velocity)
  {
    return nullptr;
  }
  vtkNew<vtkFloatArray> magnitude;
  magnitude->SetName((std::string(velocity->GetName()) + "_magnitude").c_str());
  magnitude->SetNumberOfTuples(velocity->GetNumberOfTuples());
  for (vtkIdType i = 0; i < velocity->GetNumberOfTuples(); ++i)
  {
    const double* v = velocity->GetTuple3(i);
    magnitude->SetValue(i, static_cast<float>(std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])));
  }
  points->GetPointData()->AddArray(magnitude);
  return magnitude;
}

bool ChooseValueArray(vtkPolyData* points,
  const std::string& requested,
  const std::string& file,
  bool preferSpeed,
  vtkDataArray*& chosen)
{
  if (!requested.empty())
  {
    chosen = points->GetPointData()->GetArray(requested.c_str());
    if (!chosen)
    {
      std::cerr << "raymappers-bench: " << file << " has no point array '" << requested
                << "' (--array); its point arrays: " << ListPointArrays(points) << "\n";
    }
    return chosen != nullptr;
  }
  chosen = preferSpeed ? FindSpeedArray(points) : nullptr;
  if (!chosen)
  {
    chosen = FindColorArray(points);
  }
  return true;
}

vtkDataArray* FindColorArray(vtkDataSet* points)
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

}
