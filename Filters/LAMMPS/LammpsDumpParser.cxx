// LammpsDumpParser: see the header for the file format and the behaviour on bad input.
#include "LammpsDumpParser.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <new>
#include <numeric>
#include <sstream>
#include <string_view>
#include <system_error>
#include <unordered_map>

namespace raymappers
{
namespace lammps
{
namespace
{

// Thrown inside the parser and turned into GetError() text at the public functions, so the
// many "expected X at line L" checks stay one line each.
struct ParseError
{
  std::string Message;
};

// A line longer than this is not a dump line: the file is binary or corrupt. Bounds the
// buffer a garbage file can make us allocate.
constexpr std::size_t MaxLineBytes = std::size_t(64) << 20;

// Buffered line reader over a file that also knows byte offsets and line numbers, so the
// index can record where each snapshot's atom lines start and skip them by counting
// newlines (memchr) instead of parsing them.
class LineReader
{
public:
  bool Open(const std::string& fileName, std::uint64_t offset, std::uint64_t linesBefore)
  {
    this->In.open(fileName, std::ios::binary);
    if (!this->In)
    {
      return false;
    }
    if (offset > 0)
    {
      this->In.seekg(static_cast<std::streamoff>(offset));
      if (!this->In)
      {
        return false;
      }
    }
    this->Buffer.resize(std::size_t(1) << 20);
    this->BufferOffset = offset;
    this->Line = linesBefore;
    return true;
  }

  /// Next line without its "\n" or "\r\n". False at the end of the file.
  bool Next(std::string_view& line)
  {
    std::size_t scanned = this->Pos;
    for (;;)
    {
      const char* base = this->Buffer.data();
      const void* nl = std::memchr(base + scanned, '\n', this->End - scanned);
      if (nl)
      {
        const std::size_t len = static_cast<const char*>(nl) - (base + this->Pos);
        line = std::string_view(base + this->Pos, len);
        this->Pos += len + 1;
        ++this->Line;
        this->LastUnterminated = false;
        StripCR(line);
        return true;
      }
      const std::size_t keep = this->End - this->Pos;
      if (!this->Fill())
      {
        if (this->Pos < this->End)
        {
          // Last line of the file without a newline.
          line = std::string_view(this->Buffer.data() + this->Pos, this->End - this->Pos);
          this->LastUnterminated = true;
          this->LastLineOffset = this->Offset();
          this->Pos = this->End;
          ++this->Line;
          StripCR(line);
          return true;
        }
        return false;
      }
      scanned = this->Pos + keep; // Fill moved the unread bytes to the front
    }
  }

  /// Skips up to n lines; returns how many were skipped (fewer at the end of the file).
  /// A final line without a newline counts; LastLineUnterminated() then says so.
  std::uint64_t SkipLines(std::uint64_t n)
  {
    const std::uint64_t first = this->Line;
    this->LastUnterminated = false;
    while (this->Line - first < n)
    {
      const char* base = this->Buffer.data();
      const char* p = base + this->Pos;
      const char* e = base + this->End;
      while (this->Line - first < n && p < e)
      {
        const void* nl = std::memchr(p, '\n', e - p);
        if (!nl)
        {
          break;
        }
        p = static_cast<const char*>(nl) + 1;
        ++this->Line;
      }
      this->Pos = p - base;
      // Fill keeps the unfinished line, so a line longer than MaxLineBytes stops here.
      if (this->Line - first == n || this->Fill())
      {
        continue;
      }
      if (this->Pos < this->End)
      {
        this->LastUnterminated = true;
        this->LastLineOffset = this->Offset();
        this->Pos = this->End;
        ++this->Line;
      }
      break;
    }
    return this->Line - first;
  }

  /// Byte offset of the next unread byte.
  std::uint64_t Offset() const { return this->BufferOffset + this->Pos; }
  /// Line number of the line most recently returned or skipped (1-based).
  std::uint64_t LineNumber() const { return this->Line; }
  bool LastLineUnterminated() const { return this->LastUnterminated; }
  std::uint64_t GetLastLineOffset() const { return this->LastLineOffset; }

private:
  static void StripCR(std::string_view& line)
  {
    if (!line.empty() && line.back() == '\r')
    {
      line.remove_suffix(1);
    }
  }

  // Moves the unread bytes to the front of the buffer (growing it if a line fills it) and
  // reads more. False when nothing more could be read.
  bool Fill()
  {
    if (this->Eof)
    {
      return false;
    }
    if (this->Pos > 0)
    {
      std::memmove(this->Buffer.data(), this->Buffer.data() + this->Pos, this->End - this->Pos);
      this->BufferOffset += this->Pos;
      this->End -= this->Pos;
      this->Pos = 0;
    }
    if (this->End == this->Buffer.size())
    {
      if (this->Buffer.size() >= MaxLineBytes)
      {
        throw ParseError{ "line " + std::to_string(this->Line + 1) + " is longer than " +
                          std::to_string(MaxLineBytes >> 20) +
                          " MiB: binary data or damage, not a line of a LAMMPS text dump" };
      }
      this->Buffer.resize(this->Buffer.size() * 2);
    }
    this->In.read(this->Buffer.data() + this->End,
      static_cast<std::streamsize>(this->Buffer.size() - this->End));
    const std::streamsize got = this->In.gcount();
    if (got <= 0)
    {
      this->Eof = true;
      return false;
    }
    if (!this->In)
    {
      this->Eof = true; // short read: end of file reached, the bytes read are still valid
    }
    this->End += static_cast<std::size_t>(got);
    return true;
  }

  std::ifstream In;
  std::vector<char> Buffer;
  std::size_t Pos = 0;
  std::size_t End = 0;
  std::uint64_t BufferOffset = 0;
  std::uint64_t Line = 0;
  bool Eof = false;
  bool LastUnterminated = false;
  std::uint64_t LastLineOffset = 0;
};

bool IsSpace(char c)
{
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

std::string_view Trim(std::string_view s)
{
  while (!s.empty() && IsSpace(s.front()))
  {
    s.remove_prefix(1);
  }
  while (!s.empty() && IsSpace(s.back()))
  {
    s.remove_suffix(1);
  }
  return s;
}

bool StartsWith(std::string_view s, std::string_view prefix)
{
  return s.size() >= prefix.size() && s.compare(0, prefix.size(), prefix) == 0;
}

/// Next whitespace-separated token of rest (advanced past it). False if none is left.
bool NextToken(std::string_view& rest, std::string_view& token)
{
  std::size_t i = 0;
  while (i < rest.size() && IsSpace(rest[i]))
  {
    ++i;
  }
  if (i == rest.size())
  {
    rest = std::string_view();
    return false;
  }
  std::size_t j = i;
  while (j < rest.size() && !IsSpace(rest[j]))
  {
    ++j;
  }
  token = rest.substr(i, j - i);
  rest.remove_prefix(j);
  return true;
}

std::vector<std::string_view> Tokens(std::string_view s)
{
  std::vector<std::string_view> out;
  std::string_view token;
  while (NextToken(s, token))
  {
    out.push_back(token);
  }
  return out;
}

/// A token shortened for an error message.
std::string Quote(std::string_view s)
{
  constexpr std::size_t maxChars = 60;
  std::string out;
  out.reserve(std::min(s.size(), maxChars) + 5);
  out += '\'';
  for (std::size_t i = 0; i < s.size() && i < maxChars; ++i)
  {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    out += (c >= 32 && c < 127) ? static_cast<char>(c) : '?';
  }
  if (s.size() > maxChars)
  {
    out += "...";
  }
  out += '\'';
  return out;
}

/// Parses a whole token as a double, locale-independently (std::from_chars). Accepts what
/// printf writes, including "nan", "-nan", "inf", and a leading '+'. Values beyond the double
/// range become +-inf or +-0, as strtod would give.
bool ParseDouble(std::string_view t, double& v)
{
  if (!t.empty() && t.front() == '+')
  {
    t.remove_prefix(1);
    if (!t.empty() && (t.front() == '+' || t.front() == '-'))
    {
      return false;
    }
  }
  if (t.empty())
  {
    return false;
  }
  const char* end = t.data() + t.size();
  const auto result = std::from_chars(t.data(), end, v);
  if (result.ptr != end)
  {
    return false;
  }
  if (result.ec == std::errc::result_out_of_range)
  {
    const bool negative = t.front() == '-';
    const std::size_t e = t.find_first_of("eE");
    const bool tiny = e != std::string_view::npos && e + 1 < t.size() && t[e + 1] == '-';
    v = tiny ? 0.0 : std::numeric_limits<double>::infinity();
    v = negative ? -v : v;
    return true;
  }
  return result.ec == std::errc();
}

/// Parses a whole token as an integer; also accepts an integral floating value ("3.0",
/// "1e3"), which a dump_modify format may produce.
bool ParseInt64(std::string_view t, std::int64_t& v)
{
  if (!t.empty() && t.front() == '+')
  {
    t.remove_prefix(1);
  }
  if (t.empty())
  {
    return false;
  }
  const char* end = t.data() + t.size();
  const auto result = std::from_chars(t.data(), end, v);
  if (result.ec == std::errc() && result.ptr == end)
  {
    return true;
  }
  double d = 0.0;
  if (ParseDouble(t, d) && std::isfinite(d) && d == std::floor(d) && std::fabs(d) < 9.2e18)
  {
    v = static_cast<std::int64_t>(d);
    return true;
  }
  return false;
}

std::string Where(std::uint64_t line)
{
  return "line " + std::to_string(line);
}

std::string JoinNames(const std::vector<std::string>& names)
{
  std::string out;
  for (const std::string& n : names)
  {
    out += out.empty() ? "" : " ";
    out += n;
  }
  return out;
}

std::string DescribeFrame(std::size_t index, const DumpFrameInfo& info)
{
  return "snapshot " + std::to_string(index + 1) + " (timestep " + std::to_string(info.Timestep) +
         ", line " + std::to_string(info.HeaderLine) + ")";
}

/// Explains why the start of a file does not look like a text dump, or "" if it does.
std::string SniffNotADump(const std::string& fileName, const std::string& head)
{
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(head[i]); };
  if (head.size() >= 2 && byte(0) == 0x1f && byte(1) == 0x8b)
  {
    return "'" + fileName + "' is gzip-compressed (dump .../gz): decompress it first (gunzip)";
  }
  if (head.size() >= 4 && byte(0) == 0x28 && byte(1) == 0xb5 && byte(2) == 0x2f && byte(3) == 0xfd)
  {
    return "'" + fileName + "' is zstd-compressed (dump .../zstd): decompress it first (unzstd)";
  }
  // The first line decides: a text dump starts with an ITEM: header, even when NUL bytes
  // follow (the zeros a crash can leave at the end of a file are reported by the index
  // where they start, and the snapshots before them stay readable).
  std::string_view rest(head);
  while (!rest.empty())
  {
    const std::size_t nl = rest.find('\n');
    const std::string_view line = Trim(rest.substr(0, nl));
    if (!line.empty())
    {
      if (StartsWith(line, "ITEM:"))
      {
        return std::string();
      }
      if (head.find('\0') != std::string::npos)
      {
        return "'" + fileName +
               "' is a binary file, not a text dump (a binary dump written to "
               "*.bin is converted to text with LAMMPS's binary2txt tool)";
      }
      return "'" + fileName + "' is not a LAMMPS text dump: its first line " + Quote(line) +
             " does not start with 'ITEM:' (a data file, an xyz dump, or a dump written with "
             "dump_modify header no cannot be read)";
    }
    if (nl == std::string_view::npos)
    {
      break;
    }
    rest.remove_prefix(nl + 1);
  }
  return std::string(); // blank start: the index reports what it finds
}

std::string ReadHead(const std::string& fileName, std::size_t bytes)
{
  std::ifstream in(fileName, std::ios::binary);
  std::string head(bytes, '\0');
  in.read(head.data(), static_cast<std::streamsize>(bytes));
  head.resize(in ? bytes : static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return head;
}

long long FileTimeOf(const std::string& fileName)
{
  std::error_code ec;
  const auto t = std::filesystem::last_write_time(fileName, ec);
  return ec ? 0 : static_cast<long long>(t.time_since_epoch().count());
}

/// Parses the three lines under "ITEM: BOX BOUNDS <flags>".
void ParseBox(std::string_view flagsText, LineReader& reader, DumpBox& box)
{
  const std::uint64_t headerLine = reader.LineNumber();
  bool tilted = false;
  bool general = false;
  std::vector<std::string> flags;
  for (std::string_view token : Tokens(flagsText))
  {
    if (token == "xy" || token == "xz" || token == "yz")
    {
      tilted = true;
    }
    else if (token == "abc" || token == "origin")
    {
      general = true;
    }
    else
    {
      flags.emplace_back(token);
    }
  }
  if (!flags.empty() && flags.size() != 3)
  {
    throw ParseError{ Where(headerLine) +
                      ": expected 3 boundary flags (e.g. 'pp pp pp') after "
                      "'ITEM: BOX BOUNDS', found " +
                      Quote(flagsText) };
  }
  double v[3][4] = {};
  int counts[3] = { 0, 0, 0 };
  for (int axis = 0; axis < 3; ++axis)
  {
    std::string_view line;
    if (!reader.Next(line))
    {
      throw ParseError{ "the file ends inside the BOX BOUNDS section that starts at " +
                        Where(headerLine) };
    }
    std::string_view rest = line;
    std::string_view token;
    while (NextToken(rest, token))
    {
      if (counts[axis] == 4 || !ParseDouble(token, v[axis][counts[axis]]))
      {
        throw ParseError{ Where(reader.LineNumber()) +
                          ": expected 2 to 4 numbers for a box "
                          "bound, found " +
                          Quote(line) };
      }
      ++counts[axis];
    }
  }
  // Each line must have the count the header announces: 4 for "abc origin", 3 for a tilted
  // box, else 2 (3 is also accepted: old LAMMPS versions wrote tilts without "xy xz yz").
  const int expected = general ? 4 : (tilted ? 3 : 2);
  for (int axis = 0; axis < 3; ++axis)
  {
    const bool ok = counts[axis] == expected || (!general && !tilted && counts[axis] == 3);
    if (!ok)
    {
      throw ParseError{ Where(headerLine + 1 + axis) + ": expected " + std::to_string(expected) +
                        " numbers for this box bound, found " + std::to_string(counts[axis]) };
    }
  }
  tilted = tilted || (!general && counts[0] == 3);

  box = DumpBox();
  box.Present = true;
  for (int axis = 0; axis < static_cast<int>(flags.size()); ++axis)
  {
    box.Boundary[axis] = flags[axis];
  }
  if (general)
  {
    // Lines: "Ax Ay Az xorigin", "Bx By Bz yorigin", "Cx Cy Cz zorigin".
    box.Kind = DumpBox::Shape::GeneralTriclinic;
    for (int k = 0; k < 3; ++k)
    {
      box.A[k] = v[0][k];
      box.B[k] = v[1][k];
      box.C[k] = v[2][k];
      box.Origin[k] = v[k][3];
    }
    return;
  }
  const double xy = tilted ? v[0][2] : 0.0;
  const double xz = tilted ? v[1][2] : 0.0;
  const double yz = tilted ? v[2][2] : 0.0;
  // For a tilted box LAMMPS writes the bounding box of the cell; the cell's own lo/hi are
  // recovered by removing the extent the tilts add (LAMMPS's Howto_triclinic / dump docs).
  const double xlo = v[0][0] - std::min({ 0.0, xy, xz, xy + xz });
  const double xhi = v[0][1] - std::max({ 0.0, xy, xz, xy + xz });
  const double ylo = v[1][0] - std::min(0.0, yz);
  const double yhi = v[1][1] - std::max(0.0, yz);
  const double zlo = v[2][0];
  const double zhi = v[2][1];
  box.Kind = tilted ? DumpBox::Shape::Triclinic : DumpBox::Shape::Orthogonal;
  box.Tilt[0] = xy;
  box.Tilt[1] = xz;
  box.Tilt[2] = yz;
  box.Origin[0] = xlo;
  box.Origin[1] = ylo;
  box.Origin[2] = zlo;
  // Restricted triclinic edge vectors: A = (lx,0,0), B = (xy,ly,0), C = (xz,yz,lz).
  box.A[0] = xhi - xlo;
  box.A[1] = 0.0;
  box.A[2] = 0.0;
  box.B[0] = xy;
  box.B[1] = yhi - ylo;
  box.B[2] = 0.0;
  box.C[0] = xz;
  box.C[1] = yz;
  box.C[2] = zhi - zlo;
}

/// "" if `count` atom lines can fit in the `bytes` after `line`, else why not. Every line
/// takes at least one byte, so this is known from the file size before any line is skipped
/// (a count of 5e9 in a file of a few GB fails here, not after scanning it). A sharper bound
/// from the number of columns would reject snapshots whose only fault is a short line,
/// which the reading of that snapshot reports.
std::string AtomCountBeyondFile(std::uint64_t count, std::uint64_t bytes, std::uint64_t line)
{
  if (count <= bytes)
  {
    return std::string();
  }
  return "NUMBER OF ATOMS is " + std::to_string(count) + ", but the " + std::to_string(bytes) +
         " bytes after " + Where(line) + " hold at most " + std::to_string(bytes) +
         " lines: the file is truncated or the count is wrong";
}

/// The last line of a file, from its offset (at most 64 KiB, more than any atom line).
std::string ReadLastLine(const std::string& fileName, std::uint64_t offset)
{
  std::ifstream in(fileName, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(offset));
  std::string last(1 << 16, '\0');
  in.read(last.data(), static_cast<std::streamsize>(last.size()));
  last.resize(static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return last;
}

/// True if an atom line has one value per column, each well formed.
bool IsCompleteAtomLine(const std::vector<std::string_view>& values,
  const std::vector<std::string>& names)
{
  bool complete = values.size() == names.size();
  for (std::size_t c = 0; complete && c < values.size(); ++c)
  {
    double number;
    complete = names[c] == "element" || names[c] == "typelabel" || ParseDouble(values[c], number);
  }
  return complete;
}

/// "" if the sorted ids are unique, else how many repeat, with the first few.
std::string DescribeRepeatedIds(const std::vector<std::int64_t>& ids)
{
  constexpr std::size_t examplesShown = 3;
  std::size_t repeated = 0;
  std::size_t extra = 0;
  std::string examples;
  for (std::size_t i = 0, j = 0; i < ids.size(); i = j)
  {
    for (j = i + 1; j < ids.size() && ids[j] == ids[i]; ++j)
    {
    }
    if (j - i > 1)
    {
      ++repeated;
      extra += j - i - 1;
      if (repeated <= examplesShown)
      {
        examples += (repeated > 1 ? ", id " : "id ") + std::to_string(ids[i]) + " (" +
                    std::to_string(j - i) + " times)";
      }
    }
  }
  if (repeated == 0)
  {
    return std::string();
  }
  return std::to_string(repeated) + (repeated == 1 ? " atom id occurs" : " atom ids occur") +
         " more than once (" + std::to_string(extra) + " extra atoms: " + examples +
         (repeated > examplesShown ? ", ..." : "") + "); all " + std::to_string(ids.size()) +
         " atoms are kept, sorted by id, atoms with the same id in file order";
}

/// Legacy "dump atom" files had "ITEM: ATOMS" without names; the columns were fixed.
bool LegacyAtomColumns(std::size_t count, std::vector<std::string>& names)
{
  if (count == 5)
  {
    names = { "id", "type", "xs", "ys", "zs" };
    return true;
  }
  if (count == 8)
  {
    names = { "id", "type", "xs", "ys", "zs", "ix", "iy", "iz" };
    return true;
  }
  return false;
}

} // namespace

//------------------------------------------------------------------------------
bool DumpBox::IsPeriodic(int axis) const
{
  return axis >= 0 && axis < 3 && this->Boundary[axis] == "pp";
}

void DumpBox::ScaledToCartesian(const double s[3], double r[3]) const
{
  for (int k = 0; k < 3; ++k)
  {
    r[k] = this->Origin[k] + s[0] * this->A[k] + s[1] * this->B[k] + s[2] * this->C[k];
  }
}

void DumpBox::GetBounds(double bounds[6]) const
{
  for (int k = 0; k < 3; ++k)
  {
    bounds[2 * k] = std::numeric_limits<double>::infinity();
    bounds[2 * k + 1] = -std::numeric_limits<double>::infinity();
  }
  for (int corner = 0; corner < 8; ++corner)
  {
    const double s[3] = {
      double(corner & 1), double((corner >> 1) & 1), double((corner >> 2) & 1)
    };
    double r[3];
    this->ScaledToCartesian(s, r);
    for (int k = 0; k < 3; ++k)
    {
      bounds[2 * k] = std::min(bounds[2 * k], r[k]);
      bounds[2 * k + 1] = std::max(bounds[2 * k + 1], r[k]);
    }
  }
}

void DumpFrame::Clear()
{
  *this = DumpFrame();
}

//------------------------------------------------------------------------------
TimeTable BuildTimeTable(const std::vector<DumpFrameInfo>& frames)
{
  std::vector<std::size_t> order(frames.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(),
    order.end(),
    [&](std::size_t a, std::size_t b) { return frames[a].Timestep < frames[b].Timestep; });
  TimeTable table;
  for (std::size_t i : order)
  {
    const double t = static_cast<double>(frames[i].Timestep);
    if (!table.Times.empty() && table.Times.back() == t)
    {
      table.Frames.back() = i; // same timestep again: the later snapshot wins
    }
    else
    {
      table.Times.push_back(t);
      table.Frames.push_back(i);
    }
  }
  return table;
}

std::size_t TimeTable::FrameForTime(double t) const
{
  if (this->Times.empty() || std::isnan(t))
  {
    return this->Frames.empty() ? 0 : this->Frames.front();
  }
  const double tolerance = 1e-9 * std::max(1.0, std::fabs(t));
  const auto it = std::upper_bound(this->Times.begin(), this->Times.end(), t + tolerance);
  const std::size_t index = it == this->Times.begin() ? 0 : (it - this->Times.begin()) - 1;
  return this->Frames[index];
}

//------------------------------------------------------------------------------
bool DumpParser::Fail(const std::string& message)
{
  this->Error = message;
  return false;
}

void DumpParser::Close()
{
  this->FileName.clear();
  this->Error.clear();
  this->Warnings.clear();
  this->Frames.clear();
  this->FileSize = 0;
  this->FileTime = 0;
}

bool DumpParser::IsStale() const
{
  if (this->FileName.empty())
  {
    return false;
  }
  // A file that is missing (size -1) stays missing until it appears: Open failed for it and
  // would fail the same way again.
  std::error_code ec;
  return std::filesystem::file_size(this->FileName, ec) != this->FileSize ||
         FileTimeOf(this->FileName) != this->FileTime;
}

bool DumpParser::LooksLikeDump(const std::string& fileName)
{
  std::error_code ec;
  if (!std::filesystem::is_regular_file(fileName, ec))
  {
    return false;
  }
  const std::string head = ReadHead(fileName, 4096);
  return !head.empty() && SniffNotADump(fileName, head).empty() &&
         head.find("ITEM:") != std::string::npos;
}

bool DumpParser::Open(const std::string& fileName)
{
  this->Close();
  this->FileName = fileName;
  try
  {
    // What IsStale compares with: the size is -1 for a missing file or a directory.
    std::error_code ec;
    this->FileSize = std::filesystem::file_size(fileName, ec);
    this->FileTime = FileTimeOf(fileName);
    if (fileName.empty())
    {
      return this->Fail("no file name given");
    }
    if (!std::filesystem::exists(fileName, ec))
    {
      return this->Fail("cannot open '" + fileName + "': no such file");
    }
    if (std::filesystem::is_directory(fileName, ec))
    {
      return this->Fail("cannot open '" + fileName + "': it is a directory");
    }
    LineReader reader;
    if (!reader.Open(fileName, 0, 0))
    {
      return this->Fail("cannot open '" + fileName + "' for reading: " + std::strerror(errno));
    }
    if (this->FileSize == 0)
    {
      return this->Fail("'" + fileName + "' is empty");
    }
    const std::string why = SniffNotADump(fileName, ReadHead(fileName, 4096));
    if (!why.empty())
    {
      return this->Fail(why);
    }

    // The header items of the snapshot being read; it is complete at its ATOMS section.
    DumpFrameInfo pending;
    bool inHeader = false;
    bool hasTimestep = false;
    bool hasCount = false;
    std::string units;
    bool stop = false;
    // A snapshot that stops short (a running or killed simulation): keep what is complete.
    auto truncated = [&](const std::string& message)
    {
      if (this->Frames.empty())
      {
        throw ParseError{ message };
      }
      this->Warnings.push_back(
        "'" + fileName + "': " + message + "; this incomplete snapshot is ignored");
      stop = true;
    };
    auto beginHeader = [&](std::uint64_t line)
    {
      if (hasTimestep)
      {
        throw ParseError{ Where(line) + ": a new snapshot starts, but the one at " +
                          Where(pending.HeaderLine) + " (timestep " +
                          std::to_string(pending.Timestep) + ") has no 'ITEM: ATOMS' section" };
      }
      if (!inHeader)
      {
        inHeader = true;
        pending = DumpFrameInfo();
        pending.HeaderLine = line;
        pending.Units = units;
      }
    };
    // Reads the one line under a header item; false if the file ends there.
    auto valueLine = [&](std::string_view item, std::string_view& value)
    {
      std::string_view line;
      if (!reader.Next(line))
      {
        truncated(
          "the file ends after 'ITEM: " + std::string(item) + "' at " + Where(reader.LineNumber()));
        return false;
      }
      value = Trim(line);
      return true;
    };

    std::string_view line;
    while (!stop && reader.Next(line))
    {
      const std::string_view text = Trim(line);
      const std::uint64_t lineNumber = reader.LineNumber();
      if (text.empty())
      {
        continue; // tolerated between sections
      }
      if (text.find('\0') != std::string_view::npos)
      {
        throw ParseError{ Where(lineNumber) +
                          " holds NUL bytes: binary data, not text (a crash can leave zeros at "
                          "the end of a file)" };
      }
      if (reader.LastLineUnterminated())
      {
        // LAMMPS ends every line with a newline: a header line without one was cut short.
        truncated("the file ends in the middle of " + Where(lineNumber) + " (" + Quote(text) + ")");
        break;
      }
      if (!StartsWith(text, "ITEM:"))
      {
        throw ParseError{ Where(lineNumber) + ": expected an 'ITEM:' header, found " + Quote(text) +
                          (!inHeader && !this->Frames.empty()
                              ? " (are there more atom lines than NUMBER OF ATOMS says?)"
                              : "") };
      }
      const std::string_view item = Trim(text.substr(5));
      std::string_view value;
      if (item == "UNITS")
      {
        beginHeader(lineNumber);
        if (!valueLine(item, value))
        {
          break;
        }
        units = std::string(value);
        pending.Units = units;
      }
      else if (item == "TIME")
      {
        beginHeader(lineNumber);
        if (!valueLine(item, value))
        {
          break;
        }
        if (!ParseDouble(value, pending.Time))
        {
          throw ParseError{ Where(lineNumber + 1) + ": expected the simulation time, found " +
                            Quote(value) };
        }
        pending.HasTime = true;
      }
      else if (item == "TIMESTEP")
      {
        beginHeader(lineNumber);
        if (!valueLine(item, value))
        {
          break;
        }
        if (!ParseInt64(value, pending.Timestep))
        {
          throw ParseError{ Where(lineNumber + 1) + ": expected an integer timestep, found " +
                            Quote(value) };
        }
        hasTimestep = true;
      }
      else if (item == "NUMBER OF ATOMS")
      {
        if (!hasTimestep)
        {
          throw ParseError{ Where(lineNumber) + ": 'ITEM: NUMBER OF ATOMS' before 'ITEM: "
                                                "TIMESTEP'" };
        }
        if (!valueLine(item, value))
        {
          break;
        }
        if (!ParseInt64(value, pending.NumberOfAtoms) || pending.NumberOfAtoms < 0)
        {
          throw ParseError{ Where(lineNumber + 1) + ": expected a number of atoms >= 0, found " +
                            Quote(value) };
        }
        hasCount = true;
      }
      else if (StartsWith(item, "BOX BOUNDS"))
      {
        if (!hasTimestep)
        {
          throw ParseError{ Where(lineNumber) + ": 'ITEM: BOX BOUNDS' before 'ITEM: TIMESTEP'" };
        }
        try
        {
          ParseBox(item.substr(10), reader, pending.Box);
        }
        catch (const ParseError& e)
        {
          if (StartsWith(e.Message, "the file ends"))
          {
            truncated(e.Message);
            break;
          }
          throw;
        }
      }
      else if (item == "ATOMS" || StartsWith(item, "ATOMS ") || StartsWith(item, "ATOMS\t"))
      {
        if (!hasTimestep || !hasCount)
        {
          throw ParseError{ Where(lineNumber) + ": 'ITEM: ATOMS' before " +
                            (hasTimestep ? "'ITEM: NUMBER OF ATOMS'" : "'ITEM: TIMESTEP'") };
        }
        for (std::string_view name : Tokens(item.substr(5)))
        {
          pending.ColumnNames.emplace_back(name);
        }
        pending.AtomsOffset = reader.Offset();
        pending.AtomsLine = lineNumber + 1;
        const std::uint64_t count = static_cast<std::uint64_t>(pending.NumberOfAtoms);
        std::uint64_t found = 0;
        if (pending.ColumnNames.empty() && count > 0)
        {
          // Old "dump atom" output: infer the fixed columns from the first atom line.
          std::string_view first;
          if (reader.Next(first))
          {
            found = 1;
            if (!LegacyAtomColumns(Tokens(first).size(), pending.ColumnNames))
            {
              throw ParseError{ Where(lineNumber) + ": 'ITEM: ATOMS' has no column names, and " +
                                std::to_string(Tokens(first).size()) +
                                " values per line do not match the old 'dump atom' layout" };
            }
          }
        }
        else if (pending.ColumnNames.empty())
        {
          LegacyAtomColumns(5, pending.ColumnNames);
        }
        const std::string beyond = AtomCountBeyondFile(count,
          this->FileSize - std::min(this->FileSize, std::uintmax_t(pending.AtomsOffset)),
          lineNumber);
        if (!beyond.empty())
        {
          truncated(DescribeFrame(this->Frames.size(), pending) + ": " + beyond);
          break;
        }
        found += reader.SkipLines(count - found);
        std::uint64_t complete = found;
        if (reader.LastLineUnterminated())
        {
          // LAMMPS ends every line with a newline, so the file was cut in this line (a
          // simulation killed while writing) or written by hand. As the last atom line it is
          // kept if it has all its values, well formed, but its last value may have lost
          // digits; otherwise it is not a complete line.
          const std::string last = ReadLastLine(fileName, reader.GetLastLineOffset());
          const std::vector<std::string_view> values = Tokens(last);
          const bool kept = found == count && IsCompleteAtomLine(values, pending.ColumnNames);
          complete -= kept ? 0 : 1;
          if (kept)
          {
            this->Warnings.push_back("'" + fileName + "': the file ends without a newline in " +
                                     Where(reader.LineNumber()) + ", the last atom line of " +
                                     DescribeFrame(this->Frames.size(), pending) +
                                     ": it is kept, but its last value " + Quote(values.back()) +
                                     " may have been cut short");
          }
        }
        if (complete != count)
        {
          truncated(DescribeFrame(this->Frames.size(), pending) + " is truncated: it has " +
                    std::to_string(count) + " atoms, the file ends after " +
                    std::to_string(complete) + " complete atom lines");
          break;
        }
        this->Frames.push_back(pending);
        inHeader = false;
        hasTimestep = false;
        hasCount = false;
      }
      else if (item == "NUMBER OF ENTRIES" || StartsWith(item, "ENTRIES"))
      {
        throw ParseError{
          Where(lineNumber) + ": " + Quote(text) +
          " belongs to a 'dump local' file (per-bond or per-pair values), not to a per-atom "
          "dump"
        };
      }
      else if (StartsWith(item, "DIMENSION") || StartsWith(item, "GRID"))
      {
        throw ParseError{ Where(lineNumber) + ": " + Quote(text) +
                          " belongs to a 'dump grid' file, not to a per-atom dump" };
      }
      else
      {
        throw ParseError{
          Where(lineNumber) + ": unknown section " + Quote(text) +
          " (expected TIMESTEP, NUMBER OF ATOMS, BOX BOUNDS, ATOMS, TIME or UNITS)"
        };
      }
    }
    if (inHeader && !stop && (hasTimestep || hasCount))
    {
      truncated("the file ends in the header of the snapshot at " + Where(pending.HeaderLine) +
                " (timestep " + std::to_string(pending.Timestep) + ")");
    }
    if (this->Frames.empty())
    {
      throw ParseError{ "the file contains no snapshot ('ITEM: TIMESTEP' ... 'ITEM: ATOMS')" };
    }
  }
  catch (const ParseError& e)
  {
    if (!this->Frames.empty())
    {
      // Damage after complete snapshots: keep those (the index of anything after the damage
      // cannot be trusted) and say where the file stops being readable.
      this->Warnings.push_back("'" + fileName + "': " + e.Message + "; the rest of the file (" +
                               "after snapshot " + std::to_string(this->Frames.size()) +
                               ") is ignored");
      return true;
    }
    this->Frames.clear();
    return this->Fail("'" + fileName + "': " + e.Message);
  }
  catch (const std::bad_alloc&)
  {
    this->Frames.clear();
    return this->Fail("'" + fileName + "': out of memory while indexing the file");
  }
  catch (const std::exception& e)
  {
    this->Frames.clear();
    return this->Fail("'" + fileName + "': " + e.what());
  }
  return true;
}

//------------------------------------------------------------------------------
namespace
{
enum class Role
{
  Id,
  Type,
  Position,
  Number,
  Text,
};
}

bool DumpParser::ReadFrame(std::size_t index, DumpFrame& frame)
{
  frame.Clear();
  if (index >= this->Frames.size())
  {
    return this->Fail("snapshot " + std::to_string(index + 1) + " requested, the file has " +
                      std::to_string(this->Frames.size()));
  }
  const DumpFrameInfo& info = this->Frames[index];
  frame.Info = info;
  const std::vector<std::string>& names = info.ColumnNames;
  const std::size_t columnCount = names.size();
  const std::string where = "'" + this->FileName + "', " + DescribeFrame(index, info);
  try
  {
    auto find = [&](const char* name) -> std::ptrdiff_t
    {
      const auto it = std::find(names.begin(), names.end(), name);
      return it == names.end() ? -1 : it - names.begin();
    };

    // Choose the coordinate triple.
    struct Family
    {
      PositionSource Source;
      const char* Names[3];
    };
    const Family families[] = {
      { PositionSource::Wrapped, { "x", "y", "z" } },
      { PositionSource::Unwrapped, { "xu", "yu", "zu" } },
      { PositionSource::Scaled, { "xs", "ys", "zs" } },
      { PositionSource::ScaledUnwrapped, { "xsu", "ysu", "zsu" } },
    };
    std::ptrdiff_t positionColumn[3] = { -1, -1, -1 };
    std::string partial;
    for (const Family& family : families)
    {
      std::ptrdiff_t c[3];
      int have = 0;
      for (int k = 0; k < 3; ++k)
      {
        c[k] = find(family.Names[k]);
        have += c[k] >= 0 ? 1 : 0;
      }
      if (have == 3)
      {
        frame.Positions = family.Source;
        for (int k = 0; k < 3; ++k)
        {
          positionColumn[k] = c[k];
          frame.PositionColumns[k] = family.Names[k];
        }
        break;
      }
      if (have > 0 && partial.empty())
      {
        partial = std::string(" (it has only part of ") + family.Names[0] + " " + family.Names[1] +
                  " " + family.Names[2] + ")";
      }
    }
    if (frame.Positions == PositionSource::None)
    {
      throw ParseError{ "no atom coordinates: the columns are '" + JoinNames(names) +
                        "', one of x y z, xu yu zu, xs ys zs or xsu ysu zsu is needed" + partial };
    }
    const bool scaled = frame.Positions == PositionSource::Scaled ||
                        frame.Positions == PositionSource::ScaledUnwrapped;
    if (scaled && !info.Box.Present)
    {
      throw ParseError{ "scaled coordinates (" + frame.PositionColumns[0] +
                        " ...) need the box, and the snapshot has no 'ITEM: BOX BOUNDS'" };
    }

    // Role of every column; repeated names get a suffix so arrays stay distinct.
    std::vector<Role> roles(columnCount, Role::Number);
    std::vector<int> slot(columnCount, -1); // index in Columns / TextColumns / position k
    std::vector<std::string> arrayNames(columnCount);
    std::unordered_map<std::string, int> seenNames;
    for (std::size_t c = 0; c < columnCount; ++c)
    {
      const int seen = seenNames[names[c]]++;
      arrayNames[c] = seen ? names[c] + "_" + std::to_string(seen + 1) : names[c];
      if (seen)
      {
        continue; // a repeated id/type/position column is kept as an ordinary array
      }
      if (names[c] == "id")
      {
        roles[c] = Role::Id;
      }
      else if (names[c] == "type")
      {
        roles[c] = Role::Type;
      }
      else if (names[c] == "element" || names[c] == "typelabel")
      {
        roles[c] = Role::Text;
      }
    }
    for (int k = 0; k < 3; ++k)
    {
      roles[positionColumn[k]] = Role::Position;
      slot[positionColumn[k]] = k;
    }

    const std::size_t count = static_cast<std::size_t>(info.NumberOfAtoms);
    frame.NumberOfAtoms = count;
    frame.Points.assign(3 * count, 0.0);
    frame.HasIds = find("id") >= 0;
    frame.HasTypes = find("type") >= 0;
    if (frame.HasIds)
    {
      frame.Ids.resize(count);
    }
    if (frame.HasTypes)
    {
      frame.Types.resize(count);
    }

    LineReader reader;
    if (count > 0 && !reader.Open(this->FileName, info.AtomsOffset, info.AtomsLine - 1))
    {
      throw ParseError{ "cannot open the file again: " + std::string(std::strerror(errno)) };
    }
    std::vector<std::string_view> tokens(columnCount);
    std::string_view line;
    for (std::size_t a = 0; a < count; ++a)
    {
      if (!reader.Next(line))
      {
        throw ParseError{ "the file ends after " + std::to_string(a) + " of " +
                          std::to_string(count) +
                          " atom lines (did it change since it was opened?)" };
      }
      std::string_view rest = line;
      std::size_t found = 0;
      std::string_view token;
      while (found <= columnCount && NextToken(rest, token))
      {
        if (found < columnCount)
        {
          tokens[found] = token;
        }
        ++found;
      }
      if (found != columnCount)
      {
        throw ParseError{ Where(reader.LineNumber()) + ": expected " + std::to_string(columnCount) +
                          " values (" + JoinNames(names) + "), found " +
                          std::to_string(Tokens(line).size()) };
      }
      if (a == 0)
      {
        // Decide each remaining column's kind from its first value: numbers become double
        // arrays, anything else (names, labels) text arrays.
        for (std::size_t c = 0; c < columnCount; ++c)
        {
          double probe;
          std::int64_t integer;
          if (roles[c] == Role::Number && !ParseDouble(tokens[c], probe))
          {
            roles[c] = Role::Text;
          }
          if (roles[c] == Role::Type && !ParseInt64(tokens[c], integer))
          {
            // Type labels written in place of numeric types ("C1", "Ow"): keep them as text.
            roles[c] = Role::Text;
            frame.HasTypes = false;
            frame.Types.clear();
          }
          if (roles[c] == Role::Number)
          {
            slot[c] = static_cast<int>(frame.Columns.size());
            frame.Columns.push_back({ arrayNames[c], std::vector<double>(count) });
          }
          else if (roles[c] == Role::Text)
          {
            slot[c] = static_cast<int>(frame.TextColumns.size());
            frame.TextColumns.push_back({ arrayNames[c], std::vector<std::string>(count) });
          }
        }
      }
      for (std::size_t c = 0; c < columnCount; ++c)
      {
        const std::string_view t = tokens[c];
        bool ok = true;
        switch (roles[c])
        {
          case Role::Id:
            ok = ParseInt64(t, frame.Ids[a]);
            break;
          case Role::Type:
          {
            std::int64_t type = 0;
            ok = ParseInt64(t, type) && type >= std::numeric_limits<std::int32_t>::min() &&
                 type <= std::numeric_limits<std::int32_t>::max();
            frame.Types[a] = static_cast<std::int32_t>(type);
            break;
          }
          case Role::Position:
            ok = ParseDouble(t, frame.Points[3 * a + slot[c]]);
            break;
          case Role::Number:
            ok = ParseDouble(t, frame.Columns[slot[c]].Values[a]);
            break;
          case Role::Text:
            frame.TextColumns[slot[c]].Values[a] = std::string(t);
            break;
        }
        if (!ok)
        {
          throw ParseError{
            Where(reader.LineNumber()) + ", column '" + names[c] + "': " + Quote(t) + " is not " +
            (roles[c] == Role::Id || roles[c] == Role::Type ? "an integer" : "a number")
          };
        }
      }
    }

    if (count == 0)
    {
      // No atom line to look at: every ordinary column becomes an empty numeric array, so a
      // snapshot where all atoms left still has the same arrays as the others.
      for (std::size_t c = 0; c < columnCount; ++c)
      {
        if (roles[c] == Role::Number)
        {
          frame.Columns.push_back({ arrayNames[c], std::vector<double>() });
        }
        else if (roles[c] == Role::Text)
        {
          frame.TextColumns.push_back({ arrayNames[c], std::vector<std::string>() });
        }
      }
    }

    if (scaled)
    {
      for (std::size_t a = 0; a < count; ++a)
      {
        const double s[3] = {
          frame.Points[3 * a], frame.Points[3 * a + 1], frame.Points[3 * a + 2]
        };
        info.Box.ScaledToCartesian(s, &frame.Points[3 * a]);
      }
    }

    // LAMMPS writes atoms in the order processors own them; sort by id so an atom keeps its
    // index from one snapshot to the next (when no atom is lost or created).
    if (frame.HasIds && !std::is_sorted(frame.Ids.begin(), frame.Ids.end()))
    {
      std::vector<std::size_t> order(count);
      std::iota(order.begin(), order.end(), std::size_t(0));
      std::stable_sort(order.begin(),
        order.end(),
        [&](std::size_t i, std::size_t j) { return frame.Ids[i] < frame.Ids[j]; });
      auto permute = [&](auto& values, std::size_t components)
      {
        auto sorted = values;
        for (std::size_t i = 0; i < count; ++i)
        {
          for (std::size_t k = 0; k < components; ++k)
          {
            sorted[components * i + k] = std::move(values[components * order[i] + k]);
          }
        }
        values.swap(sorted);
      };
      permute(frame.Ids, 1);
      permute(frame.Points, 3);
      if (frame.HasTypes)
      {
        permute(frame.Types, 1);
      }
      for (DumpColumn& column : frame.Columns)
      {
        permute(column.Values, 1);
      }
      for (DumpTextColumn& column : frame.TextColumns)
      {
        permute(column.Values, 1);
      }
    }
    const std::string repeated = frame.HasIds ? DescribeRepeatedIds(frame.Ids) : std::string();
    if (!repeated.empty())
    {
      frame.Warnings.push_back(where + ": " + repeated);
    }
  }
  catch (const ParseError& e)
  {
    frame.Clear();
    return this->Fail(where + ": " + e.Message);
  }
  catch (const std::bad_alloc&)
  {
    frame.Clear();
    return this->Fail(where + ": out of memory for " + std::to_string(info.NumberOfAtoms) +
                      " atoms x " + std::to_string(columnCount) + " columns");
  }
  catch (const std::exception& e)
  {
    frame.Clear();
    return this->Fail(where + ": " + e.what());
  }
  return true;
}

} // namespace lammps
} // namespace raymappers
