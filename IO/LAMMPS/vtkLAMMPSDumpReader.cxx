// vtkLAMMPSDumpReader: a thin VTK adapter over raymappers::lammps::DumpParser, which does all
// the parsing (see LammpsDumpParser.h for the format). This file only turns a parsed
// snapshot into vtkPolyData, maps VTK's time requests to snapshots and reports problems.
#include "vtkLAMMPSDumpReader.h"

#include "IO/LAMMPS/LammpsDumpParser.h"

#include "vtkCellArray.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkErrorCode.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
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
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <vector>

class vtkLAMMPSDumpReader::vtkInternals
{
public:
  raymappers::lammps::DumpParser Parser;
  raymappers::lammps::TimeTable Times;
  bool Indexed = false;  ///< Parser.open ran on the current file, which may have failed
  bool Readable = false; ///< it succeeded: there are snapshots to read
  unsigned long IndexError = vtkErrorCode::NoError;
  /// The messages given so far. A message names its file, snapshot and line, so the same
  /// text is the same problem: it is reported once, however often the pipeline reads that
  /// snapshot or, in a file series, comes back to that file (which indexes it again).
  std::set<std::string> Reported;

  /// The snapshot for the requested time (the first one without a request).
  std::size_t SnapshotFor(vtkInformation* outInfo) const
  {
    if (!outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
    {
      return this->Times.frames.front();
    }
    return this->Times.frameForTime(
      outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()));
  }

  /// Reports the messages not reported before, as errors or warnings.
  void ReportOnce(vtkObject* reader, const std::vector<std::string>& messages, bool errors)
  {
    for (const std::string& message : messages)
    {
      if (!this->Reported.insert(message).second)
      {
        continue;
      }
      if (errors)
      {
        vtkErrorWithObjectMacro(reader, << message);
      }
      else
      {
        vtkWarningWithObjectMacro(reader, << message);
      }
    }
  }
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
void vtkLAMMPSDumpReader::SetOutputPointsPrecision(int precision)
{
  if (precision < vtkAlgorithm::SINGLE_PRECISION || precision > vtkAlgorithm::DEFAULT_PRECISION)
  {
    vtkWarningMacro("OutputPointsPrecision " << precision
                                             << " is none of SINGLE_PRECISION (0), "
                                                "DOUBLE_PRECISION (1), DEFAULT_PRECISION (2): "
                                                "single precision is used");
    precision = vtkAlgorithm::SINGLE_PRECISION;
  }
  if (precision != this->OutputPointsPrecision)
  {
    this->OutputPointsPrecision = precision;
    this->Modified();
  }
}

int vtkLAMMPSDumpReader::CanReadFile(const char* fileName)
{
  return fileName && raymappers::lammps::DumpParser::looksLikeDump(fileName) ? 1 : 0;
}

int vtkLAMMPSDumpReader::GetNumberOfSnapshots()
{
  return this->Internals->Readable ? static_cast<int>(this->Internals->Parser.numberOfFrames())
                                   : 0;
}

vtkIdType vtkLAMMPSDumpReader::GetSnapshotTimestep(int index)
{
  if (index < 0 || index >= this->GetNumberOfSnapshots())
  {
    return 0;
  }
  return static_cast<vtkIdType>(this->Internals->Parser.frameInfo(index).timestep);
}

//------------------------------------------------------------------------------
void vtkLAMMPSDumpReader::UpdateIndex()
{
  vtkInternals& internals = *this->Internals;
  const std::string fileName = this->FileName ? this->FileName : "";
  // Index again only when the name changed or the file changed on disk (a running
  // simulation appending snapshots). A failed index is kept as well: ParaView asks for the
  // information of a file several times, and a bad file is not read again until it changes.
  if (internals.Indexed && internals.Parser.fileName() == fileName &&
      !internals.Parser.isStale())
  {
    return;
  }
  internals.Indexed = true;
  internals.Readable = internals.Parser.open(fileName);
  internals.Times = raymappers::lammps::TimeTable();
  if (!internals.Readable)
  {
    internals.ReportOnce(this, { internals.Parser.error() }, true);
    std::error_code ec;
    internals.IndexError = fileName.empty() ? vtkErrorCode::NoFileNameError
                           : !std::filesystem::exists(fileName, ec)
                             ? vtkErrorCode::FileNotFoundError
                             : vtkErrorCode::FileFormatError;
    return;
  }
  internals.ReportOnce(this, internals.Parser.warnings(), false);
  internals.IndexError = vtkErrorCode::NoError;
  internals.Times = raymappers::lammps::buildTimeTable(internals.Parser.frames());
}

// A file that cannot be read gives one error and an empty output, and the request returns
// success: a failure would make the executive add its own error (with a dump of the
// request) for the same problem. GetErrorCode() tells a program that it failed.
int vtkLAMMPSDumpReader::RequestInformation(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  this->UpdateIndex();
  vtkInternals& internals = *this->Internals;
  this->SetErrorCode(internals.IndexError);
  if (!internals.Readable)
  {
    return 1;
  }
  const std::vector<double>& times = internals.Times.times;
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

/// Points from x y z triples. In single precision a finite coordinate beyond the float
/// range becomes an infinity of its sign (what IEEE rounding gives; C++ leaves the
/// conversion of such a double undefined); returns how many did.
vtkIdType CopyPoints(const std::vector<double>& xyz, bool doublePrecision, vtkPoints* points)
{
  const vtkIdType values = static_cast<vtkIdType>(xyz.size());
  if (doublePrecision)
  {
    vtkNew<vtkDoubleArray> array;
    array->SetNumberOfComponents(3);
    array->SetNumberOfTuples(values / 3);
    std::copy(xyz.begin(), xyz.end(), array->GetPointer(0));
    points->SetData(array);
    return 0;
  }
  constexpr double largest = std::numeric_limits<float>::max();
  constexpr float infinity = std::numeric_limits<float>::infinity();
  vtkNew<vtkFloatArray> array;
  array->SetNumberOfComponents(3);
  array->SetNumberOfTuples(values / 3);
  float* out = array->GetPointer(0);
  vtkIdType overflows = 0;
  for (vtkIdType i = 0; i < values; ++i)
  {
    const double v = xyz[i];
    const bool beyond = std::fabs(v) > largest && std::isfinite(v);
    overflows += beyond ? 1 : 0;
    out[i] = beyond ? (v > 0 ? infinity : -infinity) : static_cast<float>(v);
  }
  points->SetData(array);
  return overflows;
}

/// One vertex cell per atom, built directly as offsets 0..n and connectivity 0..n-1.
void AddVertices(vtkIdType n, vtkPolyData* output)
{
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
}

void AddPointArrays(const raymappers::lammps::DumpFrame& frame, vtkPointData* pointData)
{
  const vtkIdType n = static_cast<vtkIdType>(frame.numberOfAtoms);
  if (frame.hasIds)
  {
    vtkNew<vtkIdTypeArray> ids;
    ids->SetName("id");
    ids->SetNumberOfValues(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      ids->SetValue(i, static_cast<vtkIdType>(frame.ids[i]));
    }
    pointData->AddArray(ids);
  }
  if (frame.hasTypes)
  {
    AddArray<vtkIntArray>(pointData, "type", frame.types.data(), n);
  }
  for (const raymappers::lammps::DumpColumn& column : frame.columns)
  {
    AddArray<vtkDoubleArray>(pointData, column.name.c_str(), column.values.data(), n);
  }
  for (const raymappers::lammps::DumpTextColumn& column : frame.textColumns)
  {
    vtkNew<vtkStringArray> text;
    text->SetName(column.name.c_str());
    text->SetNumberOfValues(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      text->SetValue(i, column.values[i]);
    }
    pointData->AddArray(text);
  }
}

/// Snapshot metadata, so a pipeline can show the step, the time and the periodic box.
void AddFieldData(const raymappers::lammps::DumpFrameInfo& info, vtkFieldData* fieldData)
{
  const vtkIdType timestep = static_cast<vtkIdType>(info.timestep);
  AddArray<vtkIdTypeArray>(fieldData, "Timestep", &timestep, 1);
  if (info.hasTime)
  {
    AddArray<vtkDoubleArray>(fieldData, "Time", &info.time, 1);
  }
  if (!info.units.empty())
  {
    vtkNew<vtkStringArray> units;
    units->SetName("Units");
    units->InsertNextValue(info.units);
    fieldData->AddArray(units);
  }
  if (info.box.present)
  {
    const raymappers::lammps::DumpBox& box = info.box;
    AddArray<vtkDoubleArray>(fieldData, "BoxOrigin", box.origin, 1, 3);
    const double edges[9] = {
      box.A[0], box.A[1], box.A[2], box.B[0], box.B[1], box.B[2], box.C[0], box.C[1], box.C[2]
    };
    AddArray<vtkDoubleArray>(fieldData, "BoxEdges", edges, 3, 3);
    const int periodic[3] = { box.isPeriodic(0), box.isPeriodic(1), box.isPeriodic(2) };
    AddArray<vtkIntArray>(fieldData, "BoxPeriodic", periodic, 1, 3);
    double bounds[6];
    box.bounds(bounds);
    AddArray<vtkDoubleArray>(fieldData, "BoxBounds", bounds, 1, 6);
  }
}
}

//------------------------------------------------------------------------------
int vtkLAMMPSDumpReader::RequestData(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkPolyData* output = vtkPolyData::GetData(outInfo);
  vtkInternals& internals = *this->Internals;
  this->SetErrorCode(internals.IndexError);
  if (!output || !internals.Readable)
  {
    return 1; // the error was reported when the file was indexed; the output stays empty
  }
  const std::size_t snapshot = internals.SnapshotFor(outInfo);
  raymappers::lammps::DumpFrame frame;
  if (!internals.Parser.readFrame(snapshot, frame))
  {
    internals.ReportOnce(this, { internals.Parser.error() }, true);
    this->SetErrorCode(vtkErrorCode::FileFormatError);
    return 1;
  }

  vtkNew<vtkPoints> points;
  const vtkIdType overflows =
    CopyPoints(frame.points, this->OutputPointsPrecision == vtkAlgorithm::DOUBLE_PRECISION, points);
  if (overflows > 0)
  {
    frame.warnings.push_back(
      "'" + internals.Parser.fileName() + "', timestep " + std::to_string(frame.info.timestep) +
      ": " + std::to_string(overflows) +
      " coordinates are beyond the range of float (3.4e38) and became infinite; set "
      "OutputPointsPrecision to double to keep them");
  }
  internals.ReportOnce(this, frame.warnings, false);
  output->SetPoints(points);
  AddVertices(points->GetNumberOfPoints(), output);
  AddPointArrays(frame, output->GetPointData());
  AddFieldData(frame.info, output->GetFieldData());
  output->GetInformation()->Set(
    vtkDataObject::DATA_TIME_STEP(), static_cast<double>(frame.info.timestep));
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
