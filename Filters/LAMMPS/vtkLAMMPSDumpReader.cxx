// vtkLAMMPSDumpReader: a thin VTK adapter over raymappers::lammps::DumpParser, which does all
// the parsing (see LammpsDumpParser.h for the format). This file only turns a parsed
// snapshot into vtkPolyData and maps VTK's time requests to snapshots.
#include "vtkLAMMPSDumpReader.h"

#include "LammpsDumpParser.h"

#include "vtkCellArray.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"

#include <algorithm>
#include <string>

class vtkLAMMPSDumpReader::vtkInternals
{
public:
  raymappers::lammps::DumpParser Parser;
  raymappers::lammps::TimeTable Times;
  bool Indexed = false;
};

vtkStandardNewMacro(vtkLAMMPSDumpReader);

//------------------------------------------------------------------------------
vtkLAMMPSDumpReader::vtkLAMMPSDumpReader()
  : FileName(nullptr)
  , OutputPointsPrecision(vtkAlgorithm::SINGLE_PRECISION)
  , Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(0);
}

vtkLAMMPSDumpReader::~vtkLAMMPSDumpReader()
{
  this->SetFileName(nullptr);
  delete this->Internals;
}

//------------------------------------------------------------------------------
int vtkLAMMPSDumpReader::CanReadFile(const char* fileName)
{
  return fileName && raymappers::lammps::DumpParser::LooksLikeDump(fileName) ? 1 : 0;
}

int vtkLAMMPSDumpReader::GetNumberOfSnapshots()
{
  return this->Internals->Indexed ? static_cast<int>(this->Internals->Parser.GetNumberOfFrames())
                                  : 0;
}

vtkIdType vtkLAMMPSDumpReader::GetSnapshotTimestep(int index)
{
  if (index < 0 || index >= this->GetNumberOfSnapshots())
  {
    return 0;
  }
  return static_cast<vtkIdType>(this->Internals->Parser.GetFrameInfo(index).Timestep);
}

//------------------------------------------------------------------------------
int vtkLAMMPSDumpReader::RequestInformation(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro("No FileName set.");
    return 0;
  }
  vtkInternals& internals = *this->Internals;
  // Index again when the name changed or the file changed on disk (a running simulation
  // appending snapshots); otherwise the index from last time is still right.
  if (!internals.Indexed || internals.Parser.GetFileName() != this->FileName ||
      internals.Parser.IsStale())
  {
    internals.Indexed = false;
    internals.Times = raymappers::lammps::TimeTable();
    if (!internals.Parser.Open(this->FileName))
    {
      vtkErrorMacro(<< internals.Parser.GetError());
      return 0;
    }
    for (const std::string& warning : internals.Parser.GetWarnings())
    {
      vtkWarningMacro(<< warning);
    }
    internals.Times = raymappers::lammps::BuildTimeTable(internals.Parser.GetFrames());
    internals.Indexed = true;
  }
  const std::vector<double>& times = internals.Times.Times;
  outInfo->Set(
    vtkStreamingDemandDrivenPipeline::TIME_STEPS(), times.data(), static_cast<int>(times.size()));
  const double range[2] = { times.front(), times.back() };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
  return 1;
}

//------------------------------------------------------------------------------
namespace
{
template<class ArrayT, class ValueT>
void AddArray(vtkFieldData* data,
  const char* name,
  const ValueT* values,
  vtkIdType tuples,
  int components = 1)
{
  vtkNew<ArrayT> array;
  array->SetName(name);
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(tuples);
  std::copy(values, values + tuples * components, array->GetPointer(0));
  data->AddArray(array);
}
}

int vtkLAMMPSDumpReader::RequestData(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkPolyData* output = vtkPolyData::GetData(outInfo);
  vtkInternals& internals = *this->Internals;
  if (!output || !internals.Indexed || internals.Times.Frames.empty())
  {
    vtkErrorMacro("No snapshot to read: the file could not be indexed.");
    return 0;
  }

  std::size_t snapshot = internals.Times.Frames.front();
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
  {
    snapshot = internals.Times.FrameForTime(
      outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()));
  }
  raymappers::lammps::DumpFrame frame;
  if (!internals.Parser.ReadFrame(snapshot, frame))
  {
    vtkErrorMacro(<< internals.Parser.GetError());
    return 0;
  }
  const vtkIdType n = static_cast<vtkIdType>(frame.NumberOfAtoms);

  vtkNew<vtkPoints> points;
  points->SetDataType(
    this->OutputPointsPrecision == vtkAlgorithm::DOUBLE_PRECISION ? VTK_DOUBLE : VTK_FLOAT);
  points->SetNumberOfPoints(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    points->SetPoint(i, &frame.Points[3 * i]);
  }
  output->SetPoints(points);

  // One vertex cell per atom, built directly as offsets 0..n and connectivity 0..n-1.
  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfValues(n + 1);
  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfValues(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    offsets->SetValue(i, i);
    connectivity->SetValue(i, i);
  }
  offsets->SetValue(n, n);
  vtkNew<vtkCellArray> verts;
  verts->SetData(offsets, connectivity);
  output->SetVerts(verts);

  vtkPointData* pointData = output->GetPointData();
  if (frame.HasIds)
  {
    vtkNew<vtkIdTypeArray> ids;
    ids->SetName("id");
    ids->SetNumberOfValues(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      ids->SetValue(i, static_cast<vtkIdType>(frame.Ids[i]));
    }
    pointData->AddArray(ids);
  }
  if (frame.HasTypes)
  {
    AddArray<vtkIntArray>(pointData, "type", frame.Types.data(), n);
  }
  for (const raymappers::lammps::DumpColumn& column : frame.Columns)
  {
    AddArray<vtkDoubleArray>(pointData, column.Name.c_str(), column.Values.data(), n);
  }
  for (const raymappers::lammps::DumpTextColumn& column : frame.TextColumns)
  {
    vtkNew<vtkStringArray> text;
    text->SetName(column.Name.c_str());
    text->SetNumberOfValues(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      text->SetValue(i, column.Values[i]);
    }
    pointData->AddArray(text);
  }

  // Snapshot metadata, so a pipeline can show the step, the time and the periodic box.
  vtkFieldData* fieldData = output->GetFieldData();
  const raymappers::lammps::DumpFrameInfo& info = frame.Info;
  const vtkIdType timestep = static_cast<vtkIdType>(info.Timestep);
  AddArray<vtkIdTypeArray>(fieldData, "Timestep", &timestep, 1);
  if (info.HasTime)
  {
    AddArray<vtkDoubleArray>(fieldData, "Time", &info.Time, 1);
  }
  if (!info.Units.empty())
  {
    vtkNew<vtkStringArray> units;
    units->SetName("Units");
    units->InsertNextValue(info.Units);
    fieldData->AddArray(units);
  }
  if (info.Box.Present)
  {
    const raymappers::lammps::DumpBox& box = info.Box;
    AddArray<vtkDoubleArray>(fieldData, "BoxOrigin", box.Origin, 1, 3);
    const double edges[9] = {
      box.A[0], box.A[1], box.A[2], box.B[0], box.B[1], box.B[2], box.C[0], box.C[1], box.C[2]
    };
    AddArray<vtkDoubleArray>(fieldData, "BoxEdges", edges, 3, 3);
    const int periodic[3] = { box.IsPeriodic(0), box.IsPeriodic(1), box.IsPeriodic(2) };
    AddArray<vtkIntArray>(fieldData, "BoxPeriodic", periodic, 1, 3);
    double bounds[6];
    box.GetBounds(bounds);
    AddArray<vtkDoubleArray>(fieldData, "BoxBounds", bounds, 1, 6);
  }

  output->GetInformation()->Set(
    vtkDataObject::DATA_TIME_STEP(), static_cast<double>(info.Timestep));
  return 1;
}

//------------------------------------------------------------------------------
void vtkLAMMPSDumpReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "OutputPointsPrecision: " << this->OutputPointsPrecision << "\n";
  os << indent << "NumberOfSnapshots: " << this->GetNumberOfSnapshots() << "\n";
}
