// vtkLAMMPSDumpReader on a real dump and on bad input.
//
// RealDump reads Testing/Data/lammps_small.dump (written by Debian's LAMMPS from
// Testing/Data/lammps_small.in: 256 Lennard-Jones atoms, types 1 and 2, timesteps 0 and 100,
// columns id type x y z vx vy vz, atom lines not sorted by id) and checks the counts, the
// time steps, the arrays and values copied from the file.
//
// The other cases write small dumps into a folder and read them as a VTK user does
// (UpdateInformation, then UpdateTimeStep for every step, twice): truncated files, more or
// fewer values than column names, repeated atom ids, atom counts the file cannot hold, NaN and
// infinite values, missing, empty and non-dump files, and 2 GiB files of garbage (written by
// WriteGarbage, deleted by RemoveGarbage). Every message of the reader, of its executive and
// of anything else (the output window) is counted: each problem gives exactly one, naming
// it, and the readable snapshots read exactly.
//
// Usage: TestLAMMPSDumpReader RealDump <path to lammps_small.dump>
//        TestLAMMPSDumpReader <case> <folder>
#include "vtkLAMMPSDumpReader.h"

#include "vtkCallbackCommand.h"
#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkErrorCode.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkOutputWindow.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringOutputWindow.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace
{
int Failures = 0;

void Check(bool ok, const std::string& what)
{
  if (!ok)
  {
    std::cerr << "FAILED: " << what << "\n";
    ++Failures;
  }
}

bool Near(double a, double b, double tolerance = 1e-5)
{
  return std::fabs(a - b) <= tolerance;
}

// The point of atom `id` (the output is sorted by id, ids are 1..256).
void AtomPoint(vtkPolyData* data, vtkIdType id, double p[3])
{
  data->GetPoint(id - 1, p);
}
}

void RealDump(const char* executable, const char* dump)
{
  vtkNew<vtkLAMMPSDumpReader> reader;
  Check(reader->CanReadFile(dump) == 1, "CanReadFile on the dump");
  Check(reader->CanReadFile(executable) == 0, "CanReadFile on the test executable");
  reader->SetFileName(dump);
  reader->UpdateInformation();

  // Time steps: the dump's timesteps.
  vtkInformation* outInfo = reader->GetOutputInformation(0);
  const int steps = outInfo->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  Check(steps == 2, "two time steps, got " + std::to_string(steps));
  if (steps == 2)
  {
    const double* times = outInfo->Get(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
    Check(times[0] == 0.0 && times[1] == 100.0, "time steps 0 and 100");
  }
  Check(reader->GetNumberOfSnapshots() == 2, "two snapshots");
  Check(reader->GetSnapshotTimestep(1) == 100, "snapshot 2 at timestep 100");

  // Timestep 0: atoms on the fcc lattice.
  reader->UpdateTimeStep(0.0);
  vtkPolyData* output = reader->GetOutput();
  Check(output->GetNumberOfPoints() == 256, "256 points");
  Check(output->GetNumberOfVerts() == 256, "256 vertex cells");
  Check(output->GetNumberOfCells() == 256, "256 cells");
  Check(output->GetPoints()->GetDataType() == VTK_FLOAT, "float points by default");
  vtkPointData* pd = output->GetPointData();
  Check(vtkIdTypeArray::SafeDownCast(pd->GetAbstractArray("id")) != nullptr,
    "'id' is a vtkIdTypeArray");
  Check(
    vtkIntArray::SafeDownCast(pd->GetAbstractArray("type")) != nullptr, "'type' is a vtkIntArray");
  for (const char* name : { "vx", "vy", "vz" })
  {
    Check(vtkDoubleArray::SafeDownCast(pd->GetAbstractArray(name)) != nullptr,
      std::string("'") + name + "' is a vtkDoubleArray");
  }
  for (const char* name : { "x", "y", "z" })
  {
    Check(pd->GetAbstractArray(name) == nullptr,
      std::string("no '") + name + "' array (it gave the positions)");
  }
  Check(pd->GetNumberOfArrays() == 5, "5 point arrays: id type vx vy vz");

  vtkIdTypeArray* ids = vtkIdTypeArray::SafeDownCast(pd->GetAbstractArray("id"));
  vtkIntArray* types = vtkIntArray::SafeDownCast(pd->GetAbstractArray("type"));
  if (ids && types)
  {
    bool sorted = true;
    int typeCount[3] = { 0, 0, 0 };
    for (vtkIdType i = 0; i < ids->GetNumberOfValues(); ++i)
    {
      sorted = sorted && ids->GetValue(i) == i + 1;
      const int t = types->GetValue(i);
      typeCount[(t == 1 || t == 2) ? t : 0]++;
    }
    Check(sorted, "ids sorted 1..256");
    Check(typeCount[1] == 128 && typeCount[2] == 128 && typeCount[0] == 0,
      "128 atoms of type 1 and 128 of type 2");
  }
  double p[3];
  // Dump line: "1 1 0 0 0 -0.356708 -0.916643 -2.7705"
  AtomPoint(output, 1, p);
  Check(p[0] == 0.0 && p[1] == 0.0 && p[2] == 0.0, "atom 1 at the origin at timestep 0");
  Check(Near(pd->GetArray("vz")->GetTuple1(0), -2.7705), "vz of atom 1 at timestep 0");
  // Dump line: "256 2 5.03879 5.87859 5.87859 1.15457 1.02948 0.00417008"
  AtomPoint(output, 256, p);
  Check(
    Near(p[0], 5.03879) && Near(p[1], 5.87859) && Near(p[2], 5.87859), "atom 256 at timestep 0");
  Check(types && types->GetValue(255) == 2, "atom 256 has type 2");
  Check(output->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP()) == 0.0, "DATA_TIME_STEP 0");

  // Timestep 100, asked for exactly and by a time between the steps.
  reader->UpdateTimeStep(100.0);
  output = reader->GetOutput();
  pd = output->GetPointData();
  Check(output->GetNumberOfPoints() == 256, "256 points at timestep 100");
  // Dump line: "1 1 0.186116 6.42836 0.121928 -0.841203 -0.510253 1.41168"
  AtomPoint(output, 1, p);
  Check(
    Near(p[0], 0.186116) && Near(p[1], 6.42836) && Near(p[2], 0.121928), "atom 1 at timestep 100");
  Check(pd->GetArray("vx") && Near(pd->GetArray("vx")->GetTuple1(0), -0.841203),
    "vx of atom 1 at timestep 100");
  Check(
    output->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP()) == 100.0, "DATA_TIME_STEP 100");
  vtkFieldData* fd = output->GetFieldData();
  Check(fd->GetArray("Timestep") && fd->GetArray("Timestep")->GetTuple1(0) == 100.0,
    "field data Timestep 100");
  Check(fd->GetArray("BoxBounds") &&
          Near(fd->GetArray("BoxBounds")->GetComponent(0, 1), 6.7183847655300291, 1e-12),
    "field data BoxBounds xhi");
  Check(fd->GetArray("BoxPeriodic") && fd->GetArray("BoxPeriodic")->GetComponent(0, 2) == 1.0,
    "periodic z");
  // All atoms inside the periodic box (x y z are wrapped coordinates).
  double bounds[6];
  output->GetBounds(bounds);
  Check(bounds[0] >= 0.0 && bounds[1] <= 6.7184 && bounds[4] >= 0.0 && bounds[5] <= 6.7184,
    "atoms inside the box");

  reader->UpdateTimeStep(50.0);
  AtomPoint(reader->GetOutput(), 1, p);
  Check(p[0] == 0.0 && p[1] == 0.0, "time 50 reads timestep 0 (the one before)");

  // Double precision on request.
  reader->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  reader->UpdateTimeStep(100.0);
  Check(reader->GetOutput()->GetPoints()->GetDataType() == VTK_DOUBLE, "double points");
  AtomPoint(reader->GetOutput(), 1, p);
  Check(p[0] == 0.186116, "atom 1 x exact in double");
}

//------------------------------------------------------------------------------
// Bad input.
namespace
{
namespace fs = std::filesystem;

// Every message a reader gives while it is observed: its own errors and warnings, its
// executive's, and whatever reaches the output window from anywhere else.
class MessageLog
{
public:
  explicit MessageLog(vtkAlgorithm* reader)
  {
    this->Observer->SetCallback(&MessageLog::Record);
    this->Observer->SetClientData(this);
    for (vtkObject* source :
      { static_cast<vtkObject*>(reader), static_cast<vtkObject*>(reader->GetExecutive()) })
    {
      source->AddObserver(vtkCommand::ErrorEvent, this->Observer);
      source->AddObserver(vtkCommand::WarningEvent, this->Observer);
    }
    this->Previous = vtkOutputWindow::GetInstance();
    vtkOutputWindow::SetInstance(this->Window);
  }
  ~MessageLog() { vtkOutputWindow::SetInstance(this->Previous); }

  std::size_t Count() const
  {
    return this->Errors.size() + this->Warnings.size() +
           (this->Window->GetOutput().empty() ? 0 : 1);
  }
  std::vector<std::string> Errors;
  std::vector<std::string> Warnings;

  /// Exactly one message, an error or a warning as `error` says, containing every part.
  void ExpectOne(bool error, const std::vector<std::string>& parts, const std::string& what) const
  {
    const std::vector<std::string>& kind = error ? this->Errors : this->Warnings;
    bool named = kind.size() == 1;
    for (const std::string& part : parts)
    {
      named = named && kind[0].find(part) != std::string::npos;
    }
    Check(this->Count() == 1 && named,
      what + ": exactly one " + (error ? "error" : "warning") + " naming '" + parts.front() + "'" +
        this->Describe());
  }
  void ExpectNone(const std::string& what) const
  {
    Check(this->Count() == 0, what + ": no message" + this->Describe());
  }

private:
  static void Record(vtkObject*, unsigned long event, void* clientData, void* callData)
  {
    auto* self = static_cast<MessageLog*>(clientData);
    const std::string text = callData ? static_cast<const char*>(callData) : "";
    (event == vtkCommand::ErrorEvent ? self->Errors : self->Warnings).push_back(text);
  }
  std::string Describe() const
  {
    std::string out;
    for (const std::string& e : this->Errors)
    {
      out += "\n    error: " + e;
    }
    for (const std::string& w : this->Warnings)
    {
      out += "\n    warning: " + w;
    }
    if (!this->Window->GetOutput().empty())
    {
      out += "\n    output window: " + this->Window->GetOutput();
    }
    return out;
  }

  vtkNew<vtkCallbackCommand> Observer;
  vtkNew<vtkStringOutputWindow> Window;
  vtkSmartPointer<vtkOutputWindow> Previous;
};

std::string Write(const fs::path& path, const std::string& text)
{
  std::ofstream out(path, std::ios::binary);
  out << text;
  return path.string();
}

// Atom `id` of the snapshot at `step` sits at (id, step / 100, 0.5) with q = 10 id + step / 100.
std::string AtomLine(int id, int step)
{
  const std::string s = std::to_string(step / 100);
  return std::to_string(id) + " 1 " + std::to_string(id) + " " + s + " 0.5 " +
         std::to_string(10 * id + step / 100);
}

// A snapshot of `atoms` atoms written in reverse id order (12 lines for 3 atoms: the atom
// lines are lines 10 to 12 of it). `count` replaces the NUMBER OF ATOMS if given.
std::string Snapshot(int step, int atoms = 3, const std::string& count = "")
{
  std::string text = "ITEM: TIMESTEP\n" + std::to_string(step) + "\nITEM: NUMBER OF ATOMS\n" +
                     (count.empty() ? std::to_string(atoms) : count) +
                     "\nITEM: BOX BOUNDS pp pp pp\n0 10\n0 10\n0 10\n"
                     "ITEM: ATOMS id type x y z q\n";
  for (int id = atoms; id >= 1; --id)
  {
    text += AtomLine(id, step) + "\n";
  }
  return text;
}

const std::string ThreeSteps = Snapshot(0) + Snapshot(100) + Snapshot(200);

std::vector<double> TimeSteps(vtkAlgorithm* reader)
{
  vtkInformation* info = reader->GetOutputInformation(0);
  const int n = info->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  const double* t = info->Get(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
  return n > 0 ? std::vector<double>(t, t + n) : std::vector<double>();
}

// True if the output holds Snapshot(step)'s atoms exactly, sorted by id.
bool HoldsSnapshot(vtkPolyData* output, int step, int atoms = 3)
{
  vtkDataArray* q = output->GetPointData()->GetArray("q");
  vtkDataArray* ids = output->GetPointData()->GetArray("id");
  bool same =
    output->GetNumberOfPoints() == atoms && output->GetNumberOfVerts() == atoms && q && ids;
  for (vtkIdType i = 0; same && i < atoms; ++i)
  {
    double p[3];
    output->GetPoint(i, p);
    const double id = double(i + 1);
    same = ids->GetTuple1(i) == id && p[0] == id && p[1] == double(step / 100) && p[2] == 0.5 &&
           q->GetTuple1(i) == 10 * id + step / 100;
  }
  return same;
}

// Reads every time step twice, as an animation going back and forth does; `good` are the
// steps that must read exactly, every other step must give an empty output.
void ReadAllSteps(vtkLAMMPSDumpReader* reader,
  const std::vector<int>& good,
  const std::string& what)
{
  for (int pass = 0; pass < 2; ++pass)
  {
    for (int step : { 0, 100, 200 })
    {
      reader->UpdateTimeStep(step);
      vtkPolyData* output = reader->GetOutput();
      if (std::find(good.begin(), good.end(), step) != good.end())
      {
        Check(HoldsSnapshot(output, step) && reader->GetErrorCode() == vtkErrorCode::NoError,
          what + ": timestep " + std::to_string(step) + " reads exactly");
      }
    }
  }
}

// A reader on `path`, its information updated with `log` observing it.
struct Opened
{
  vtkNew<vtkLAMMPSDumpReader> Reader;
  std::unique_ptr<MessageLog> Log;
  explicit Opened(const std::string& path)
    : Log(new MessageLog(Reader))
  {
    this->Reader->SetFileName(path.c_str());
    this->Reader->UpdateInformation();
  }
};

// A dump cut where a killed simulation leaves it: the complete snapshots read, one warning
// names the cut one; cut before any snapshot is complete, one error and an empty output.
void Truncated(const fs::path& dir)
{
  const std::string& full = ThreeSteps;
  const std::size_t third = full.find("ITEM: TIMESTEP\n200");
  struct Cut
  {
    std::string Name;
    std::size_t Size;
    std::vector<std::string> Parts; // the warning names these
  };
  // The third snapshot starts at line 25; its atom lines are 34 (id 3), 35 and 36 (id 1).
  const std::vector<Cut> cuts = {
    { "in the header",
      full.find("3\n", full.find("NUMBER OF ATOMS", third)),
      { "ends after 'ITEM: NUMBER OF ATOMS' at line 27" } },
    { "in a header line",
      full.find("UNDS", third),
      { "ends in the middle of line 29", "'ITEM: BOX BO'" } },
    { "in the ATOMS block",
      full.find(AtomLine(2, 200), third),
      { "timestep 200", "is truncated: it has 3 atoms", "after 1 complete atom lines" } },
    { "in an atom line",
      full.find(AtomLine(2, 200), third) + 5,
      { "timestep 200", "after 1 complete atom lines" } },
  };
  for (const Cut& cut : cuts)
  {
    Opened dump(Write(dir / "cut.dump", full.substr(0, cut.Size)));
    Check(TimeSteps(dump.Reader) == std::vector<double>{ 0, 100 }, "cut " + cut.Name + ": 2 steps");
    ReadAllSteps(dump.Reader, { 0, 100 }, "cut " + cut.Name);
    dump.Log->ExpectOne(false, cut.Parts, "cut " + cut.Name);
  }

  // Cut inside the last number of the file ("12" of "1 1 1 2 0.5 12" left as "1"): every
  // value is there, so the snapshot is kept; the warning says which value may be short.
  {
    Opened dump(Write(dir / "number.dump", full.substr(0, full.size() - 2)));
    Check(TimeSteps(dump.Reader) == std::vector<double>{ 0, 100, 200 }, "cut in a number: 3 steps");
    ReadAllSteps(dump.Reader, { 0, 100 }, "cut in a number");
    dump.Reader->UpdateTimeStep(200);
    vtkDataArray* q = dump.Reader->GetOutput()->GetPointData()->GetArray("q");
    Check(dump.Reader->GetOutput()->GetNumberOfPoints() == 3 && q && q->GetTuple1(0) == 1.0 &&
            q->GetTuple1(2) == 32.0,
      "cut in a number: timestep 200 read as the file has it");
    dump.Log->ExpectOne(false, { "line 36", "'1' may have been cut short" }, "cut in a number");
  }

  // Cut before the first snapshot is complete: one error, an empty output.
  {
    Opened dump(Write(dir / "first.dump", full.substr(0, full.find("ITEM: BOX"))));
    dump.Reader->Update();
    Check(dump.Reader->GetOutput()->GetNumberOfPoints() == 0 && TimeSteps(dump.Reader).empty() &&
            dump.Reader->GetErrorCode() == vtkErrorCode::FileFormatError,
      "cut in the first snapshot: empty output, FileFormatError");
    dump.Log->ExpectOne(true,
      { "the file ends in the header of the snapshot at line 1" },
      "cut in the first snapshot");
  }
}

// A middle snapshot with an atom line missing (NUMBER OF ATOMS says 3, 2 lines follow): it
// is dropped with one warning, and the next snapshot's header is not taken for its atoms, so
// the snapshots before and after it read exactly.
void ShortSnapshot(const fs::path& dir)
{
  std::string middle = Snapshot(100);
  middle.erase(middle.find(AtomLine(2, 100)), AtomLine(2, 100).size() + 1);
  Opened dump(Write(dir / "short.dump", Snapshot(0) + middle + Snapshot(200)));
  Check(TimeSteps(dump.Reader) == std::vector<double>{ 0, 200 }, "short snapshot: 2 steps");
  ReadAllSteps(dump.Reader, { 0, 200 }, "short snapshot");
  // The middle snapshot starts at line 13; its atom lines are 22 and 23.
  dump.Log->ExpectOne(false,
    { "timestep 100", "only 2 of its 3 atom lines", "'ITEM:' header at line 24" },
    "short snapshot");
}

// A line with a value too many or too few: its snapshot gives one error (line, both counts)
// and an empty output, the other snapshots read exactly.
void ExtraColumns(const fs::path& dir)
{
  // Snapshot 2 (timestep 100) starts at line 13; its atom line of id 2 is line 23.
  const std::string line = AtomLine(2, 100);
  for (const auto& [changed, found] :
    { std::pair<std::string, std::string>{ line + " 7", "7" }, { line.substr(0, 7), "4" } })
  {
    std::string text = ThreeSteps;
    text.replace(text.find(line), line.size(), changed);
    Opened dump(Write(dir / "columns.dump", text));
    const std::string what = found + " values";
    Check(TimeSteps(dump.Reader) == std::vector<double>{ 0, 100, 200 }, what + ": 3 steps");
    ReadAllSteps(dump.Reader, { 0, 200 }, what);
    dump.Reader->UpdateTimeStep(100);
    Check(dump.Reader->GetOutput()->GetNumberOfPoints() == 0 &&
            dump.Reader->GetErrorCode() == vtkErrorCode::FileFormatError,
      what + ": timestep 100 is empty, FileFormatError");
    dump.Log->ExpectOne(true,
      { "line 23: expected 6 values (id type x y z q), found " + found, "timestep 100" },
      what);
  }
}

// Ids 2 and 4 twice in the second snapshot: all atoms kept, sorted, one warning.
void DuplicateIds(const fs::path& dir)
{
  const std::string second = "ITEM: TIMESTEP\n100\nITEM: NUMBER OF ATOMS\n6\n"
                             "ITEM: BOX BOUNDS pp pp pp\n0 10\n0 10\n0 10\n"
                             "ITEM: ATOMS id type x y z q\n"
                             "4 1 4.0 1 0.5 41\n2 1 2.0 1 0.5 21\n1 1 1.0 1 0.5 11\n"
                             "2 1 2.5 1 0.5 22\n3 1 3.0 1 0.5 31\n4 1 4.5 1 0.5 42\n";
  Opened dump(Write(dir / "duplicates.dump", Snapshot(0) + second));
  for (int pass = 0; pass < 2; ++pass)
  {
    dump.Reader->UpdateTimeStep(0);
    Check(HoldsSnapshot(dump.Reader->GetOutput(), 0), "timestep 0 (unique ids) reads exactly");
    dump.Reader->UpdateTimeStep(100);
    vtkPolyData* output = dump.Reader->GetOutput();
    vtkDataArray* ids = output->GetPointData()->GetArray("id");
    vtkDataArray* q = output->GetPointData()->GetArray("q");
    bool kept = output->GetNumberOfPoints() == 6 && ids && q;
    const double expectedIds[6] = { 1, 2, 2, 3, 4, 4 };
    const double expectedX[6] = { 1.0, 2.0, 2.5, 3.0, 4.0, 4.5 };
    const double expectedQ[6] = { 11, 21, 22, 31, 41, 42 };
    for (vtkIdType i = 0; kept && i < 6; ++i)
    {
      kept = ids->GetTuple1(i) == expectedIds[i] && output->GetPoint(i)[0] == expectedX[i] &&
             q->GetTuple1(i) == expectedQ[i];
    }
    Check(kept, "repeated ids: all 6 atoms kept, sorted by id, equal ids in file order");
  }
  dump.Log->ExpectOne(false,
    { "2 atom ids occur more than once (2 extra atoms: id 2 (2 times), id 4 (2 times))",
      "timestep 100" },
    "repeated ids");
}

// NUMBER OF ATOMS beyond 32 bits (and beyond the file), negative or not a number.
void AtomCountOverflow(const fs::path& dir)
{
  for (const char* count : { "5000000000", "4294967301" })
  {
    Opened dump(Write(dir / "huge.dump", Snapshot(0, 3, count)));
    dump.Reader->Update();
    Check(dump.Reader->GetOutput()->GetNumberOfPoints() == 0 &&
            dump.Reader->GetErrorCode() == vtkErrorCode::FileFormatError,
      std::string(count) + " atoms in a small file: empty output, FileFormatError");
    dump.Log->ExpectOne(true,
      { std::string("NUMBER OF ATOMS is ") + count, "bytes after line 9 hold at most" },
      std::string(count) + " atoms");
  }
  {
    Opened dump(
      Write(dir / "lasthuge.dump", Snapshot(0) + Snapshot(100) + Snapshot(200, 3, "4294967301")));
    Check(TimeSteps(dump.Reader) == std::vector<double>{ 0, 100 }, "2^32+5 atoms last: 2 steps");
    ReadAllSteps(dump.Reader, { 0, 100 }, "2^32+5 atoms last");
    dump.Log->ExpectOne(false,
      { "NUMBER OF ATOMS is 4294967301", "timestep 200" },
      "2^32+5 atoms in the last snapshot");
  }
  for (const char* count : { "-7", "-5000000000", "99999999999999999999", "1e30", "nan", "three" })
  {
    Opened dump(Write(dir / "count.dump", Snapshot(0, 3, count)));
    dump.Reader->Update();
    Check(dump.Reader->GetOutput()->GetNumberOfPoints() == 0,
      std::string("count '") + count + "': empty output");
    dump.Log->ExpectOne(true,
      { std::string("line 4: expected a number of atoms >= 0, found '") + count + "'" },
      std::string("count '") + count + "'");
  }
}

// NaN and infinities are passed on as they are; beyond the float range a coordinate of a
// single precision output becomes infinite, with one warning; double keeps it.
void SpecialValues(const fs::path& dir)
{
  const std::string text = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n4\n"
                           "ITEM: BOX BOUNDS pp pp pp\n0 10\n0 10\n0 10\n"
                           "ITEM: ATOMS id type x y z q\n"
                           "1 1 nan 0 -nan -nan\n"
                           "2 1 inf -inf 0 inf\n"
                           "3 1 1e39 -1e39 1e400 1e-400\n"
                           "4 1 1 2 3 4\n";
  const std::string path = Write(dir / "special.dump", text);
  for (int precision : { vtkAlgorithm::SINGLE_PRECISION, vtkAlgorithm::DOUBLE_PRECISION })
  {
    const bool single = precision == vtkAlgorithm::SINGLE_PRECISION;
    const std::string what = single ? "single" : "double";
    vtkNew<vtkLAMMPSDumpReader> reader;
    MessageLog log(reader);
    reader->SetOutputPointsPrecision(precision);
    reader->SetFileName(path.c_str());
    for (int pass = 0; pass < 2; ++pass)
    {
      reader->Modified();
      reader->Update();
    }
    vtkPolyData* output = reader->GetOutput();
    vtkDataArray* q = output->GetPointData()->GetArray("q");
    const double inf = std::numeric_limits<double>::infinity();
    double p[4][3];
    for (int i = 0; i < 4 && output->GetNumberOfPoints() == 4; ++i)
    {
      output->GetPoint(i, p[i]);
    }
    Check(output->GetNumberOfPoints() == 4 && q, what + ": all 4 atoms, NaN ones included");
    if (output->GetNumberOfPoints() != 4 || !q)
    {
      continue;
    }
    Check(std::isnan(p[0][0]) && p[0][1] == 0 && std::isnan(p[0][2]), what + ": NaN passed on");
    Check(p[1][0] == inf && p[1][1] == -inf, what + ": infinities passed on");
    Check(single ? (p[2][0] == inf && p[2][1] == -inf) : (p[2][0] == 1e39 && p[2][1] == -1e39),
      what + ": 1e39 is " + (single ? "infinite in float" : "kept in double"));
    Check(p[2][2] == inf && p[3][0] == 1 && p[3][1] == 2 && p[3][2] == 3,
      what + ": 1e400 is infinite, the finite atom exact");
    Check(std::isnan(q->GetTuple1(0)) && q->GetTuple1(1) == inf && q->GetTuple1(2) == 0.0 &&
            q->GetTuple1(3) == 4,
      what + ": values NaN, inf, 0 (1e-400), 4 passed on");
    if (single)
    {
      log.ExpectOne(false, { "2 coordinates are beyond the range of float" }, what);
    }
    else
    {
      log.ExpectNone(what);
    }
  }
}

// An OutputPointsPrecision that is none of VTK's three: single precision, one warning.
void OutputPointsPrecision(const fs::path& dir)
{
  const std::string path = Write(dir / "good.dump", ThreeSteps);
  for (int precision : { -1, 3, std::numeric_limits<int>::max() })
  {
    const std::string what = "OutputPointsPrecision " + std::to_string(precision);
    vtkNew<vtkLAMMPSDumpReader> reader;
    MessageLog log(reader);
    reader->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
    reader->SetOutputPointsPrecision(precision);
    reader->SetFileName(path.c_str());
    reader->UpdateInformation();
    ReadAllSteps(reader, { 0, 100, 200 }, what);
    Check(reader->GetOutputPointsPrecision() == vtkAlgorithm::SINGLE_PRECISION &&
            reader->GetOutput()->GetPoints()->GetDataType() == VTK_FLOAT,
      what + ": single precision");
    log.ExpectOne(false, { what + " is none of" }, what);
  }
}

// Files that are not dumps: one error each, naming the problem; an empty output.
void NotADump(const fs::path& dir)
{
  struct Bad
  {
    std::string Path;
    std::string Named;
    unsigned long Code;
  };
  const std::vector<Bad> files = {
    { (dir / "missing.dump").string(), "no such file", vtkErrorCode::FileNotFoundError },
    { Write(dir / "empty.dump", ""), "is empty", vtkErrorCode::FileFormatError },
    { Write(dir / "blank.dump", "\n  \n\n"),
      "contains no snapshot",
      vtkErrorCode::FileFormatError },
    { Write(dir / "data.dump", "LAMMPS data file\n\n3 atoms\n"),
      "is not a LAMMPS text dump",
      vtkErrorCode::FileFormatError },
    { Write(dir / "binary.dump",
        std::string("\x7f"
                    "ELF\0\0\x01",
          7)),
      "is a binary file",
      vtkErrorCode::FileFormatError },
    { Write(dir / "dump.gz", std::string("\x1f\x8b\x08\x00", 4)),
      "gzip-compressed",
      vtkErrorCode::FileFormatError },
    { dir.string(), "it is a directory", vtkErrorCode::FileFormatError },
    { "", "no file name given", vtkErrorCode::NoFileNameError },
  };
  for (const Bad& bad : files)
  {
    const std::string what = "'" + fs::path(bad.Path).filename().string() + "'";
    vtkNew<vtkLAMMPSDumpReader> reader;
    Check(reader->CanReadFile(bad.Path.c_str()) == 0, what + ": CanReadFile 0");
    MessageLog log(reader);
    reader->SetFileName(bad.Path.empty() ? nullptr : bad.Path.c_str());
    for (int step : { 0, 100, 0 })
    {
      reader->UpdateTimeStep(step);
    }
    Check(reader->GetOutput()->GetNumberOfPoints() == 0 && reader->GetErrorCode() == bad.Code,
      what + ": empty output, error code " + vtkErrorCode::GetStringFromErrorCode(bad.Code));
    log.ExpectOne(true, { bad.Named }, what);
  }
  // A reader that failed reads the next file as if nothing happened.
  vtkNew<vtkLAMMPSDumpReader> reader;
  MessageLog log(reader);
  reader->SetFileName(files[0].Path.c_str());
  reader->Update();
  reader->SetFileName(Write(dir / "good.dump", ThreeSteps).c_str());
  reader->UpdateInformation();
  ReadAllSteps(reader, { 0, 100, 200 }, "a good file after a missing one");
  log.ExpectOne(true, { "no such file" }, "a good file after a missing one");
}

//------------------------------------------------------------------------------
// 2 GiB of garbage, written once by WriteGarbage for this test and the pvpython one.
const std::uintmax_t GarbageBytes = std::uintmax_t(2) << 30;

// Sparse files (resize_file writes no data) after a text head, and one of pseudo-random
// bytes written as a repeated 1 MiB block.
void WriteGarbage(const fs::path& dir)
{
  fs::create_directories(dir);
  const std::vector<std::pair<std::string, std::string>> heads = {
    { "zeros.dump", "" },
    { "header-zeros.dump", Snapshot(0, 10).substr(0, Snapshot(0, 10).find(AtomLine(8, 0))) },
    { "count-zeros.dump", Snapshot(0, 0, "5000000000") },
    { "good-zeros.dump", Snapshot(0) },
  };
  for (const auto& [name, head] : heads)
  {
    fs::resize_file(Write(dir / name, head), GarbageBytes);
  }
  const auto start = std::chrono::steady_clock::now();
  std::vector<char> block(std::size_t(1) << 20);
  std::mt19937_64 random(2024);
  for (std::size_t i = 0; i < block.size(); i += 8)
  {
    const std::uint64_t r = random();
    std::memcpy(block.data() + i, &r, 8);
  }
  std::ofstream out(dir / "random.dump", std::ios::binary);
  for (std::uintmax_t written = 0; written < GarbageBytes && out; written += block.size())
  {
    out.write(block.data(), static_cast<std::streamsize>(block.size()));
  }
  out.close();
  const double seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  Check(out.good() && fs::file_size(dir / "random.dump") == GarbageBytes,
    "2 GiB of pseudo-random bytes written");
  std::printf("wrote 2 GiB of pseudo-random bytes in %.2f s; 4 sparse 2 GiB files\n", seconds);
}

// The reader's peak resident memory so far, from /proc (Linux), in MiB; -1 if unknown.
double PeakMemoryMiB()
{
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
  {
    if (line.rfind("VmHWM:", 0) == 0)
    {
      return std::stod(line.substr(6)) / 1024.0; // the value is in kB
    }
  }
  return -1.0;
}

// Each garbage file fails fast with one message (the good snapshot before the zeros stays
// readable), reading at most the 64 MiB a line may have: the peak memory stays far below the
// file size. The times are printed, not asserted.
void Garbage2GB(const fs::path& dir)
{
  struct Garbage
  {
    std::string Name;
    bool Error;
    std::vector<std::string> Parts;
  };
  const std::vector<Garbage> files = {
    { "zeros.dump", true, { "is a binary file" } },
    { "random.dump", true, { "is a binary file" } },
    { "header-zeros.dump", true, { "line 12 is longer than 64 MiB" } },
    { "count-zeros.dump", true, { "NUMBER OF ATOMS is 5000000000", "hold at most" } },
    { "good-zeros.dump", false, { "line 13 is longer than 64 MiB", "after snapshot 1" } },
  };
  for (const Garbage& garbage : files)
  {
    const fs::path path = dir / garbage.Name;
    if (!fs::exists(path) || fs::file_size(path) != GarbageBytes)
    {
      Check(false, path.string() + " is 2 GiB (written by the WriteGarbage fixture)");
      continue;
    }
    const auto start = std::chrono::steady_clock::now();
    Opened dump(path.string());
    dump.Reader->Update();
    const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%-18s read in %.3f s, peak memory %.0f MiB\n",
      garbage.Name.c_str(),
      seconds,
      PeakMemoryMiB());
    dump.Log->ExpectOne(garbage.Error, garbage.Parts, garbage.Name);
    if (garbage.Error)
    {
      Check(dump.Reader->GetOutput()->GetNumberOfPoints() == 0, garbage.Name + ": empty output");
    }
    else
    {
      Check(HoldsSnapshot(dump.Reader->GetOutput(), 0), garbage.Name + ": snapshot 1 reads");
    }
  }
  Check(PeakMemoryMiB() < 512, "peak memory below 512 MiB");
}
}

int main(int argc, char* argv[])
{
  const std::string mode = argc > 1 ? argv[1] : "";
  const std::map<std::string, void (*)(const fs::path&)> cases = {
    { "Truncated", Truncated },
    { "ShortSnapshot", ShortSnapshot },
    { "ExtraColumns", ExtraColumns },
    { "DuplicateIds", DuplicateIds },
    { "AtomCountOverflow", AtomCountOverflow },
    { "SpecialValues", SpecialValues },
    { "NotADump", NotADump },
    { "OutputPointsPrecision", OutputPointsPrecision },
    { "WriteGarbage", WriteGarbage },
    { "Garbage2GB", Garbage2GB },
    { "RemoveGarbage", [](const fs::path& dir) { fs::remove_all(dir); } },
  };
  if (argc < 3 || (mode != "RealDump" && !cases.count(mode)))
  {
    std::cerr << "usage: " << argv[0] << " RealDump lammps_small.dump | <case> <folder>\n";
    return EXIT_FAILURE;
  }
  if (mode == "RealDump")
  {
    RealDump(argv[0], argv[2]);
  }
  else
  {
    const fs::path dir = argv[2];
    fs::create_directories(dir);
    cases.at(mode)(dir);
  }
  if (Failures)
  {
    std::cerr << Failures << " check(s) failed\n";
    return EXIT_FAILURE;
  }
  std::cout << "TestLAMMPSDumpReader " << mode << ": all checks passed\n";
  return EXIT_SUCCESS;
}
