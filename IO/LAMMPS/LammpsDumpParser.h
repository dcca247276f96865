// LammpsDumpParser: reads LAMMPS text dump files ("dump ... atom" and "dump ... custom").
// Plain C++17, no VTK: vtkLAMMPSDumpReader is the VTK adapter over it.
//
// The format, as LAMMPS writes it (one block per snapshot, repeated):
//
//   ITEM: UNITS                    optional (dump_modify units yes), first snapshot only
//   lj
//   ITEM: TIME                     optional (dump_modify time yes): simulation time
//   0.5
//   ITEM: TIMESTEP
//   100
//   ITEM: NUMBER OF ATOMS
//   256
//   ITEM: BOX BOUNDS pp pp pp      boundary flags per axis (p periodic, f fixed, s/m shrink)
//   xlo xhi                        orthogonal box: one line per axis
//   ylo yhi
//   zlo zhi
//   ITEM: ATOMS id type x y z vx   column names, then NUMBER OF ATOMS lines
//   1 1 0.0 0.0 0.0 0.25
//   ...
//
// Box variants:
//   "BOX BOUNDS xy xz yz pp pp pp": restricted triclinic box; each line is "lo_bound hi_bound
//     tilt", where lo/hi_bound are the axis-aligned bounding box of the tilted cell (so they
//     include the tilt) and the tilts are xy, xz, yz in that order.
//   "BOX BOUNDS abc origin pp pp pp": general triclinic box (dump_modify triclinic/general);
//     each line is "vx vy vz origin_component" for the edge vectors A, B, C.
//
// Positions come from one of the coordinate triples, in this order of preference:
//   x y z (wrapped into the box), xu yu zu (unwrapped), xs ys zs (scaled to [0,1] in box
//   units: r = origin + xs A + ys B + zs C), xsu ysu zsu (scaled and unwrapped).
// Columns "id" and "type" are integers; "element" and "typelabel" (and any other column
// whose first value is not a number) are text; every other column is a double.
//
// Robustness: a malformed file gives a clear error naming the line and what was expected.
// Damage after at least one complete snapshot (typically a truncated last snapshot of a
// simulation still writing or killed) is a warning instead: the complete snapshots before it
// stay readable. A snapshot whose atom lines end early at the next "ITEM:" header is dropped
// with a warning; the snapshots after it stay readable. Values such as "nan" or "inf" are
// kept as they are.
#ifndef RayMappers_LammpsDumpParser_h
#define RayMappers_LammpsDumpParser_h

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace raymappers
{
namespace lammps
{

/// The simulation box of one snapshot as a parallelepiped: Origin + a A + b B + c C with
/// a, b, c in [0, 1].
struct DumpBox
{
  enum class Shape
  {
    Orthogonal,       ///< "BOX BOUNDS pp pp pp"
    Triclinic,        ///< "BOX BOUNDS xy xz yz pp pp pp" (restricted triclinic)
    GeneralTriclinic, ///< "BOX BOUNDS abc origin pp pp pp"
  };

  bool present = false; ///< false when the snapshot had no BOX BOUNDS section
  Shape kind = Shape::Orthogonal;
  double origin[3] = { 0.0, 0.0, 0.0 };
  double A[3] = { 1.0, 0.0, 0.0 };
  double B[3] = { 0.0, 1.0, 0.0 };
  double C[3] = { 0.0, 0.0, 1.0 };
  /// Tilt factors xy, xz, yz (restricted triclinic only, else 0).
  double tilt[3] = { 0.0, 0.0, 0.0 };
  /// Boundary flags as written, e.g. "pp", "fs", "mm"; empty if the header had none.
  std::string boundary[3];

  /// True if the axis has the periodic flag "pp".
  bool isPeriodic(int axis) const;
  /// Cartesian position of the scaled coordinates s (box units).
  void scaledToCartesian(const double s[3], double r[3]) const;
  /// Axis-aligned bounds of the parallelepiped: xmin, xmax, ymin, ymax, zmin, zmax.
  void bounds(double bounds[6]) const;
};

/// What the index knows about one snapshot without reading its atoms.
struct DumpFrameInfo
{
  std::int64_t timestep = 0;
  bool hasTime = false; ///< the snapshot had "ITEM: TIME"
  double time = 0.0;
  std::string units; ///< "ITEM: UNITS" (written once; carried to later snapshots)
  std::int64_t numberOfAtoms = 0;
  DumpBox box;
  std::vector<std::string> columnNames;
  std::uint64_t atomsOffset = 0; ///< byte offset of the first atom line
  std::uint64_t atomsLine = 0;   ///< 1-based line number of the first atom line
  std::uint64_t headerLine = 0;  ///< 1-based line number where the snapshot starts
};

/// Which coordinate columns gave DumpFrame::Points.
enum class PositionSource
{
  None,
  Wrapped,         ///< x y z
  Unwrapped,       ///< xu yu zu
  Scaled,          ///< xs ys zs
  ScaledUnwrapped, ///< xsu ysu zsu
};

/// A numeric per-atom column other than positions, id and type.
struct DumpColumn
{
  std::string name;
  std::vector<double> values;
};

/// A text per-atom column (element names, type labels).
struct DumpTextColumn
{
  std::string name;
  std::vector<std::string> values;
};

/// One snapshot's atoms, sorted by id when the dump has an "id" column.
struct DumpFrame
{
  DumpFrameInfo info;
  std::size_t numberOfAtoms = 0;
  PositionSource positions = PositionSource::None;
  /// Names of the three columns used for positions, e.g. "x" "y" "z".
  std::string positionColumns[3];
  /// Cartesian positions, 3 per atom (scaled coordinates are converted with the box).
  std::vector<double> points;
  bool hasIds = false;
  std::vector<std::int64_t> ids;
  bool hasTypes = false;
  std::vector<std::int32_t> types;
  /// Every other numeric column, in file order. Unused coordinate columns (e.g. xu when
  /// x y z gave the positions) are kept here as well.
  std::vector<DumpColumn> columns;
  std::vector<DumpTextColumn> textColumns;
  /// What reading found wrong without stopping it (e.g. atom ids that occur twice).
  std::vector<std::string> warnings;

  void clear();
};

/// Sorted, unique time values (the timesteps) and, for each, the snapshot to read.
/// When a timestep occurs more than once (a run restarted and appended to the same dump),
/// the last snapshot with it wins: it is the one the rerun produced.
struct TimeTable
{
  std::vector<double> times;
  std::vector<std::size_t> frames;

  /// The snapshot for a requested time: the one with the largest time <= t, or the first
  /// one if t is before all of them (a small tolerance absorbs rounding). Requires
  /// at least one entry; returns 0 for an empty table.
  std::size_t frameForTime(double t) const;
};

TimeTable buildTimeTable(const std::vector<DumpFrameInfo>& frames);

/// Indexes a dump file's snapshots, then reads any of them on request.
class DumpParser
{
public:
  /// Indexes the snapshots of a file (headers only; atom lines are counted, not parsed).
  /// Returns false and sets error() if the file cannot be read or has no complete
  /// snapshot. If the file is truncated or damaged after complete snapshots, those are kept
  /// and warnings() says what was dropped and where.
  bool open(const std::string& fileName);
  void close();

  /// True if the file's size or modification time changed since open (e.g. a running
  /// simulation appended snapshots, or a missing file appeared): the caller should open() it
  /// again. False for a file that is as it was, including one open() failed on.
  bool isStale() const;

  const std::string& fileName() const { return this->FileName; }
  const std::string& error() const { return this->Error; }
  const std::vector<std::string>& warnings() const { return this->Warnings; }

  std::size_t numberOfFrames() const { return this->Frames.size(); }
  const DumpFrameInfo& frameInfo(std::size_t i) const { return this->Frames[i]; }
  const std::vector<DumpFrameInfo>& frames() const { return this->Frames; }

  /// Reads snapshot i into frame. Returns false and sets error() on malformed atom lines,
  /// missing coordinate columns, or a file that changed since open().
  bool readFrame(std::size_t i, DumpFrame& frame);

  /// Quick test used by readers' CanReadFile: does the file start like a text dump?
  static bool looksLikeDump(const std::string& fileName);

private:
  bool fail(const std::string& message);

  std::string FileName;
  std::string Error;
  std::vector<std::string> Warnings;
  std::vector<DumpFrameInfo> Frames;
  std::uintmax_t FileSize = 0;
  long long FileTime = 0;
};

} // namespace lammps
} // namespace raymappers

#endif
