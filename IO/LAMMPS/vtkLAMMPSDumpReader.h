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
 * again; otherwise the index is reused.
 *
 * Bad input: every problem gives one error or warning that names the file, the snapshot and
 * the line, once (reading the same snapshot again, or coming back to a file of a series,
 * repeats nothing), and never a crash.
 * - A file that cannot be read (missing, empty, not a text dump, binary, no complete
 *   snapshot, a NUMBER OF ATOMS the file is too short to hold) gives one error and an empty
 *   output; the request still succeeds (a failed request would make the executive add a
 *   second error for the same problem), and GetErrorCode() says it failed (NoFileNameError,
 *   FileNotFoundError or FileFormatError).
 * - A file truncated or damaged after complete snapshots (a simulation killed while
 *   writing; zeros left by a crash) gives one warning; the complete snapshots stay readable.
 *   A last line without its newline (LAMMPS ends every line with one) that has all its values
 *   is kept, with a warning that its last value may have lost digits.
 * - A snapshot with an atom line of more or fewer values than the ITEM: ATOMS header names,
 *   or a value that is not a number, gives one error when that snapshot is read (the line and
 *   both counts) and an empty output for it; the other snapshots read as usual.
 * - Atom ids that occur more than once in a snapshot: every atom is kept (none is dropped
 *   silently), sorted by id, atoms with the same id in file order, and one warning counts
 *   the repeated ids and the extra atoms.
 * - NaN and infinite values ("nan", "inf", 1e400) in coordinates and columns are passed on
 *   as they are (the mappers skip NaN particles with their own warning). In single precision
 *   a coordinate beyond the float range becomes infinite, with one warning.
 *
 * Not handled: compressed (.gz, .zst) and binary dumps (convert with gunzip / binary2txt), one
 * file per processor (dump.%), "dump local" and "dump grid" files. A series of one-snapshot
 * files (dump.*) is read as a file series by ParaView.
 */
#ifndef vtkLAMMPSDumpReader_h
#define vtkLAMMPSDumpReader_h

#include "RayMappersIOModule.h"
#include "vtkPolyDataAlgorithm.h"

class RAYMAPPERSIO_EXPORT vtkLAMMPSDumpReader : public vtkPolyDataAlgorithm
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
  /// 6 significant digits). Other arrays are always double. Any other value is replaced by
  /// SINGLE_PRECISION with a warning.
  void SetOutputPointsPrecision(int precision);
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
  /// Indexes the file if it is new or changed on disk, and reports what indexing found.
  void UpdateIndex();

  vtkLAMMPSDumpReader(const vtkLAMMPSDumpReader&) = delete;
  void operator=(const vtkLAMMPSDumpReader&) = delete;

  class vtkInternals;
  vtkInternals* Internals;
};

#endif
