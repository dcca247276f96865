// Reads Testing/Data/lammps_small.dump (written by Debian's LAMMPS from
// Testing/Data/lammps_small.in: 256 Lennard-Jones atoms, types 1 and 2, timesteps 0 and 100,
// columns id type x y z vx vy vz, atom lines not sorted by id) with vtkLAMMPSDumpReader and
// checks the counts, the time steps, the arrays and values copied from the file.
// Usage: TestLAMMPSDumpReader <path to lammps_small.dump>
#include "vtkLAMMPSDumpReader.h"

#include "vtkCallbackCommand.h"
#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>

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

void CountErrors(vtkObject*, unsigned long, void* clientData, void*)
{
  ++*static_cast<int*>(clientData);
}

// The point of atom `id` (the output is sorted by id, ids are 1..256).
void AtomPoint(vtkPolyData* data, vtkIdType id, double p[3])
{
  data->GetPoint(id - 1, p);
}
}

int main(int argc, char* argv[])
{
  if (argc < 2)
  {
    std::cerr << "usage: " << argv[0] << " lammps_small.dump\n";
    return EXIT_FAILURE;
  }
  vtkNew<vtkLAMMPSDumpReader> reader;
  Check(reader->CanReadFile(argv[1]) == 1, "CanReadFile on the dump");
  Check(reader->CanReadFile(argv[0]) == 0, "CanReadFile on the test executable");
  reader->SetFileName(argv[1]);
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

  // A missing file: an error (observed here so the test log stays clean), no crash, no data.
  int errors = 0;
  vtkNew<vtkCallbackCommand> onError;
  onError->SetCallback(CountErrors);
  onError->SetClientData(&errors);
  vtkNew<vtkLAMMPSDumpReader> missing;
  missing->AddObserver(vtkCommand::ErrorEvent, onError);
  missing->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, onError);
  missing->SetFileName((std::string(argv[1]) + ".does-not-exist").c_str());
  missing->Update();
  Check(errors > 0, "an error for a missing file");
  Check(missing->GetOutput()->GetNumberOfPoints() == 0, "no points for a missing file");

  if (Failures)
  {
    std::cerr << Failures << " check(s) failed\n";
    return EXIT_FAILURE;
  }
  std::cout << "TestLAMMPSDumpReader: all checks passed\n";
  return EXIT_SUCCESS;
}
