/**
 * @class   vtkLAMMPSDumpReader
 * @brief   Reads LAMMPS text dump files ("dump ... atom", "dump ... custom") as particles over
 * time.
 *
 * Output: a vtkPolyData with one point and one vertex cell per atom, sorted by atom id when the
 * dump has an "id" column (so an atom keeps its index over time unless atoms are lost).
 * Point arrays: every dump column except the three used for positions. "id" is a
 * vtkIdTypeArray, "type" a vtkIntArray, "element"/"typelabel" vtkStringArrays, all others
 * vtkDoubleArrays named as in the dump ("vx", "c_pe", "f_ave[2]" ...).
 * Positions come from x y z, else xu yu zu, else scaled xs ys zs / xsu ysu zsu (converted with
 * the snapshot's box, orthogonal or triclinic).
 * Field data: "Timestep" (vtkIdTypeArray), "Time" (if the dump has ITEM: TIME), "Units" (if it
 * has ITEM: UNITS), and the box: "BoxOrigin" (3), "BoxEdges" (3 tuples: the edge vectors
 * A, B, C), "BoxPeriodic" (3 ints), "BoxBounds" (6).
 *
 * Time: TIME_STEPS are the dump's timestep values, sorted; a request between two of them
 * reads the earlier one. If a timestep occurs twice (a restarted run appended to the file),
 * the later snapshot is used. If the file changed on disk (a running simulation appending
 * snapshots), the next update after Modified() (in ParaView: File > Reload Files) indexes it
 * again; otherwise the index is reused. A truncated last snapshot (or anything after damage in
 * the file) is skipped with a warning that names the line.
 *
 * Not handled: compressed (.gz, .zst) and binary dumps (convert with gunzip / binary2txt), one
 * file per processor (dump.%), "dump local" and "dump grid" files. A series of one-snapshot
 * files (dump.*) is read as a file series by ParaView.
 */
#ifndef vtkLAMMPSDumpReader_h
#define vtkLAMMPSDumpReader_h

#include "RayMappersFiltersModule.h"
#include "vtkPolyDataAlgorithm.h"

class RAYMAPPERSFILTERS_EXPORT vtkLAMMPSDumpReader : public vtkPolyDataAlgorithm
{
public:
  static vtkLAMMPSDumpReader* New();
  vtkTypeMacro(vtkLAMMPSDumpReader, vtkPolyDataAlgorithm) void PrintSelf(ostream& os,
    vtkIndent indent) override;

  ///@{
  /// The dump file to read.
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  ///@{
  /// Precision of the output points: vtkAlgorithm::SINGLE_PRECISION (default, float) or
  /// DOUBLE_PRECISION. DEFAULT_PRECISION means float as well (dumps are text, usually with
  /// 6 significant digits). Other arrays are always double.
  vtkSetClampMacro(OutputPointsPrecision, int, SINGLE_PRECISION, DEFAULT_PRECISION);
  vtkGetMacro(OutputPointsPrecision, int);
  ///@}

  /// 1 if the file starts like a LAMMPS text dump (first line "ITEM: ..."), else 0.
  int CanReadFile(const char* fileName);

  /// Number of snapshots found by the last RequestInformation (UpdateInformation()).
  int GetNumberOfSnapshots();
  /// Timestep of a snapshot in file order, after UpdateInformation(); 0 if out of range.
  vtkIdType GetSnapshotTimestep(int index);

protected:
  vtkLAMMPSDumpReader();
  ~vtkLAMMPSDumpReader() override;

  int RequestInformation(vtkInformation* request,
    vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request,
    vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  char* FileName;
  int OutputPointsPrecision;

private:
  vtkLAMMPSDumpReader(const vtkLAMMPSDumpReader&) = delete;
  void operator=(const vtkLAMMPSDumpReader&) = delete;

  class vtkInternals;
  vtkInternals* Internals;
};

#endif
