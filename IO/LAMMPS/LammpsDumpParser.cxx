// LammpsDumpParser: see the header for the file format and the behaviour on bad input.
// open() checks the file (checkFile), then indexes its snapshots (SnapshotIndexer: one function
// per header section, the atom block's extent counted, not parsed). readFrame reads one
// snapshot (readSnapshot: the coordinate columns, every column's role, the atom lines into
// arrays, scaled to Cartesian coordinates, sorted by id).
#include "IO/LAMMPS/LammpsDumpParser.h"

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

// Thrown inside the parser and turned into error() text at the public functions, so the
// many "expected X at line L" checks stay one line each.
struct ParseError
{
  std::string message;
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
  bool open(const std::string& fileName, std::uint64_t offset, std::uint64_t linesBefore)
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
  bool next(std::string_view& line)
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
        stripCR(line);
        return true;
      }
      const std::size_t keep = this->End - this->Pos;
      if (!this->fill())
      {
        if (this->Pos < this->End)
        {
          // Last line of the file without a newline.
          line = std::string_view(this->Buffer.data() + this->Pos, this->End - this->Pos);
          this->LastUnterminated = true;
          this->LastLineOffset = this->offset();
          this->Pos = this->End;
          ++this->Line;
          stripCR(line);
          return true;
        }
        return false;
      }
      scanned = this->Pos + keep; // Fill moved the unread bytes to the front
    }
  }

  /// Skips up to n lines; returns how many were skipped. Fewer at the end of the file, or
  /// before a line that starts with "ITEM:" (a snapshot with fewer atom lines than it
  /// announced: the next section's header is not an atom line); atHeader() then says so and
  /// next() returns that line. A final line without a newline counts; lastLineUnterminated()
  /// then says so.
  std::uint64_t skipLines(std::uint64_t n)
  {
    const std::uint64_t first = this->Line;
    this->LastUnterminated = false;
    this->StoppedAtHeader = false;
    while (this->Line - first < n && !this->StoppedAtHeader)
    {
      this->scanLines(first + n);
      // Fill keeps the unfinished line, so a line longer than MaxLineBytes stops here.
      if (this->Line - first == n || this->StoppedAtHeader || this->fill())
      {
        continue;
      }
      if (this->Pos < this->End)
      {
        this->LastUnterminated = true;
        this->LastLineOffset = this->offset();
        this->Pos = this->End;
        ++this->Line;
      }
      break;
    }
    return this->Line - first;
  }

  /// Byte offset of the next unread byte.
  std::uint64_t offset() const { return this->BufferOffset + this->Pos; }
  /// Line number of the line most recently returned or skipped (1-based).
  std::uint64_t lineNumber() const { return this->Line; }
  bool lastLineUnterminated() const { return this->LastUnterminated; }
  bool atHeader() const { return this->StoppedAtHeader; }
  std::uint64_t lastLineOffset() const { return this->LastLineOffset; }

private:
  static void stripCR(std::string_view& line)
  {
    if (!line.empty() && line.back() == '\r')
    {
      line.remove_suffix(1);
    }
  }

  // Counts the buffered lines, up to line number `last`, stopping before a line that starts
  // with "ITEM:" (LAMMPS writes headers at the start of a line). A header cut by the end of
  // the buffer has no newline in it, so the scan stops there and sees the whole tag after
  // Fill, which keeps the unfinished line.
  void scanLines(std::uint64_t last)
  {
    constexpr char tag[] = "ITEM:";
    constexpr std::ptrdiff_t tagSize = sizeof(tag) - 1;
    const char* base = this->Buffer.data();
    const char* p = base + this->Pos;
    const char* e = base + this->End;
    std::uint64_t line = this->Line; // a local: memchr cannot change it
    while (line < last)
    {
      if (e - p >= tagSize && std::memcmp(p, tag, tagSize) == 0)
      {
        this->StoppedAtHeader = true;
        break;
      }
      const void* nl = std::memchr(p, '\n', e - p);
      if (!nl)
      {
        break;
      }
      p = static_cast<const char*>(nl) + 1;
      ++line;
    }
    this->Line = line;
    this->Pos = p - base;
  }

  // Moves the unread bytes to the front of the buffer (growing it if a line fills it) and
  // reads more. False when nothing more could be read.
  bool fill()
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
  bool StoppedAtHeader = false;
  std::uint64_t LastLineOffset = 0;
};

bool isSpace(char c)
{
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

std::string_view trim(std::string_view s)
{
  while (!s.empty() && isSpace(s.front()))
  {
    s.remove_prefix(1);
  }
  while (!s.empty() && isSpace(s.back()))
  {
    s.remove_suffix(1);
  }
  return s;
}

bool startsWith(std::string_view s, std::string_view prefix)
{
  return s.size() >= prefix.size() && s.compare(0, prefix.size(), prefix) == 0;
}

/// Next whitespace-separated token of rest (advanced past it). False if none is left.
bool nextToken(std::string_view& rest, std::string_view& token)
{
  std::size_t i = 0;
  while (i < rest.size() && isSpace(rest[i]))
  {
    ++i;
  }
  if (i == rest.size())
  {
    rest = std::string_view();
    return false;
  }
  std::size_t j = i;
  while (j < rest.size() && !isSpace(rest[j]))
  {
    ++j;
  }
  token = rest.substr(i, j - i);
  rest.remove_prefix(j);
  return true;
}

std::vector<std::string_view> splitTokens(std::string_view s)
{
  std::vector<std::string_view> out;
  std::string_view token;
  while (nextToken(s, token))
  {
    out.push_back(token);
  }
  return out;
}

/// A token shortened for an error message.
std::string quote(std::string_view s)
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
bool parseDouble(std::string_view t, double& v)
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
bool parseInt64(std::string_view t, std::int64_t& v)
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
  if (parseDouble(t, d) && std::isfinite(d) && d == std::floor(d) && std::fabs(d) < 9.2e18)
  {
    v = static_cast<std::int64_t>(d);
    return true;
  }
  return false;
}

std::string where(std::uint64_t line)
{
  return "line " + std::to_string(line);
}

std::string joinNames(const std::vector<std::string>& names)
{
  std::string out;
  for (const std::string& n : names)
  {
    out += out.empty() ? "" : " ";
    out += n;
  }
  return out;
}

std::string describeFrame(std::size_t index, const DumpFrameInfo& info)
{
  return "snapshot " + std::to_string(index + 1) + " (timestep " + std::to_string(info.timestep) +
         ", line " + std::to_string(info.headerLine) + ")";
}

/// Explains why the start of a file does not look like a text dump, or "" if it does.
std::string sniffNotADump(const std::string& fileName, const std::string& head)
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
    const std::string_view line = trim(rest.substr(0, nl));
    if (!line.empty())
    {
      if (startsWith(line, "ITEM:"))
      {
        return std::string();
      }
      if (head.find('\0') != std::string::npos)
      {
        return "'" + fileName +
               "' is a binary file, not a text dump (a binary dump written to "
               "*.bin is converted to text with LAMMPS's binary2txt tool)";
      }
      return "'" + fileName + "' is not a LAMMPS text dump: its first line " + quote(line) +
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

std::string readHead(const std::string& fileName, std::size_t bytes)
{
  std::ifstream in(fileName, std::ios::binary);
  std::string head(bytes, '\0');
  in.read(head.data(), static_cast<std::streamsize>(bytes));
  head.resize(in ? bytes : static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return head;
}

long long fileTimeOf(const std::string& fileName)
{
  std::error_code ec;
  const auto t = std::filesystem::last_write_time(fileName, ec);
  return ec ? 0 : static_cast<long long>(t.time_since_epoch().count());
}

/// The header of a BOX BOUNDS section: "xy xz yz" announce a restricted triclinic box, "abc
/// origin" a general one, the other words are the boundary flags (none, or one per axis).
struct BoxHeader
{
  bool tilted = false;
  bool general = false;
  std::vector<std::string> flags;
};

/// The numbers of the three lines under the header, up to 4 per line.
struct BoxLines
{
  double V[3][4] = {};
  int counts[3] = { 0, 0, 0 };
};

/// Reads the words after "ITEM: BOX BOUNDS" (on line `headerLine`).
BoxHeader parseBoxHeader(std::string_view flagsText, std::uint64_t headerLine)
{
  BoxHeader header;
  for (std::string_view token : splitTokens(flagsText))
  {
    if (token == "xy" || token == "xz" || token == "yz")
    {
      header.tilted = true;
    }
    else if (token == "abc" || token == "origin")
    {
      header.general = true;
    }
    else
    {
      header.flags.emplace_back(token);
    }
  }
  if (!header.flags.empty() && header.flags.size() != 3)
  {
    throw ParseError{ where(headerLine) +
                      ": expected 3 boundary flags (e.g. 'pp pp pp') after "
                      "'ITEM: BOX BOUNDS', found " +
                      quote(flagsText) };
  }
  return header;
}

/// Reads the numbers of the three lines after the header, at most 4 per line.
BoxLines readBoxLines(LineReader& reader, std::uint64_t headerLine)
{
  BoxLines lines;
  for (int axis = 0; axis < 3; ++axis)
  {
    std::string_view line;
    if (!reader.next(line))
    {
      throw ParseError{ "the file ends inside the BOX BOUNDS section that starts at " +
                        where(headerLine) };
    }
    std::string_view rest = line;
    std::string_view token;
    int& count = lines.counts[axis];
    while (nextToken(rest, token))
    {
      if (count == 4 || !parseDouble(token, lines.V[axis][count]))
      {
        throw ParseError{ where(reader.lineNumber()) +
                          ": expected 2 to 4 numbers for a box "
                          "bound, found " +
                          quote(line) };
      }
      ++count;
    }
  }
  return lines;
}

/// Each line must have the count the header announces: 4 for "abc origin", 3 for a tilted
/// box, else 2 (3 is also accepted: old LAMMPS versions wrote tilts without "xy xz yz").
void checkBoxLineCounts(const BoxHeader& header, const BoxLines& lines, std::uint64_t headerLine)
{
  const int expected = header.general ? 4 : (header.tilted ? 3 : 2);
  for (int axis = 0; axis < 3; ++axis)
  {
    const int count = lines.counts[axis];
    const bool ok = count == expected || (!header.general && !header.tilted && count == 3);
    if (!ok)
    {
      throw ParseError{ where(headerLine + 1 + axis) + ": expected " + std::to_string(expected) +
                        " numbers for this box bound, found " + std::to_string(count) };
    }
  }
}

/// A general triclinic box from its lines "Ax Ay Az xorigin", "Bx By Bz yorigin",
/// "Cx Cy Cz zorigin".
void setGeneralTriclinicBox(const double v[3][4], DumpBox& box)
{
  box.kind = DumpBox::Shape::GeneralTriclinic;
  for (int k = 0; k < 3; ++k)
  {
    box.A[k] = v[0][k];
    box.B[k] = v[1][k];
    box.C[k] = v[2][k];
    box.origin[k] = v[k][3];
  }
}

/// An orthogonal or restricted triclinic box from its lines "lo hi [tilt]".
void setRestrictedBox(const double v[3][4], bool tilted, DumpBox& box)
{
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
  box.kind = tilted ? DumpBox::Shape::Triclinic : DumpBox::Shape::Orthogonal;
  box.tilt[0] = xy;
  box.tilt[1] = xz;
  box.tilt[2] = yz;
  box.origin[0] = xlo;
  box.origin[1] = ylo;
  box.origin[2] = zlo;
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

/// Parses the three lines under "ITEM: BOX BOUNDS <flags>".
void parseBox(std::string_view flagsText, LineReader& reader, DumpBox& box)
{
  const std::uint64_t headerLine = reader.lineNumber();
  const BoxHeader header = parseBoxHeader(flagsText, headerLine);
  const BoxLines lines = readBoxLines(reader, headerLine);
  checkBoxLineCounts(header, lines, headerLine);
  box = DumpBox();
  box.present = true;
  for (int axis = 0; axis < static_cast<int>(header.flags.size()); ++axis)
  {
    box.boundary[axis] = header.flags[axis];
  }
  if (header.general)
  {
    setGeneralTriclinicBox(lines.V, box);
  }
  else
  {
    setRestrictedBox(lines.V, header.tilted || lines.counts[0] == 3, box);
  }
}

/// "" if `count` atom lines can fit in the `bytes` after `line`, else why not. Every line
/// takes at least one byte, so this is known from the file size before any line is skipped
/// (a count of 5e9 in a file of a few GB fails here, not after scanning it). A sharper bound
/// from the number of columns would reject snapshots whose only fault is a short line,
/// which the reading of that snapshot reports.
std::string atomCountBeyondFile(std::uint64_t count, std::uint64_t bytes, std::uint64_t line)
{
  if (count <= bytes)
  {
    return std::string();
  }
  return "NUMBER OF ATOMS is " + std::to_string(count) + ", but the " + std::to_string(bytes) +
         " bytes after " + where(line) + " hold at most " + std::to_string(bytes) +
         " lines: the file is truncated or the count is wrong";
}

/// The last line of a file, from its offset (at most 64 KiB, more than any atom line).
std::string readLastLine(const std::string& fileName, std::uint64_t offset)
{
  std::ifstream in(fileName, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(offset));
  std::string last(1 << 16, '\0');
  in.read(last.data(), static_cast<std::streamsize>(last.size()));
  last.resize(static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return last;
}

/// True if an atom line has one value per column, each well formed.
bool isCompleteAtomLine(const std::vector<std::string_view>& values,
  const std::vector<std::string>& names)
{
  bool complete = values.size() == names.size();
  for (std::size_t c = 0; complete && c < values.size(); ++c)
  {
    double number;
    complete = names[c] == "element" || names[c] == "typelabel" || parseDouble(values[c], number);
  }
  return complete;
}

/// "" if the sorted ids are unique, else how many repeat, with the first few.
std::string describeRepeatedIds(const std::vector<std::int64_t>& ids)
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
bool legacyAtomColumns(std::size_t count, std::vector<std::string>& names)
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

/// Why a file cannot be indexed, found before any of its lines is read, or "" if it can be:
/// no name, missing, a directory, unreadable, empty, or not a text dump by its first bytes.
/// Opens `reader` at the start of the file on the way.
std::string checkFile(const std::string& fileName, std::uintmax_t fileSize, LineReader& reader)
{
  std::error_code ec;
  if (fileName.empty())
  {
    return "no file name given";
  }
  if (!std::filesystem::exists(fileName, ec))
  {
    return "cannot open '" + fileName + "': no such file";
  }
  if (std::filesystem::is_directory(fileName, ec))
  {
    return "cannot open '" + fileName + "': it is a directory";
  }
  if (!reader.open(fileName, 0, 0))
  {
    return "cannot open '" + fileName + "' for reading: " + std::strerror(errno);
  }
  if (fileSize == 0)
  {
    return "'" + fileName + "' is empty";
  }
  return sniffNotADump(fileName, readHead(fileName, 4096));
}

/// Throws "line L: expected <what>, found '<value>'" unless ok.
void expectValue(bool ok, std::uint64_t line, const char* what, std::string_view value)
{
  if (!ok)
  {
    throw ParseError{ where(line) + ": expected " + what + ", found " + quote(value) };
  }
}

/// The index of a dump (DumpParser::open): reads every snapshot's header sections (UNITS,
/// TIME, TIMESTEP, NUMBER OF ATOMS, BOX BOUNDS, ATOMS with the column names) and skips its
/// atom lines by counting them. A problem throws ParseError, except a snapshot cut short
/// after complete ones (a simulation still writing, or killed), which ends the index with a
/// warning. The section functions return false when indexing stops there.
class SnapshotIndexer
{
public:
  SnapshotIndexer(const std::string& fileName,
    std::uintmax_t fileSize,
    LineReader& reader,
    std::vector<DumpFrameInfo>& frames,
    std::vector<std::string>& warnings)
    : FileName(fileName)
    , FileSize(fileSize)
    , Reader(reader)
    , Frames(frames)
    , Warnings(warnings)
  {
  }

  /// Indexes the file from the reader's position to its end (or to a truncated snapshot).
  void run()
  {
    std::string_view line;
    bool more = true;
    while (more && this->Reader.next(line))
    {
      more = this->indexLine(line);
    }
    if (more && this->InHeader && (this->HasTimestep || this->HasCount))
    {
      this->truncated("the file ends in the header of the snapshot at " +
                      where(this->Pending.headerLine) + " (timestep " +
                      std::to_string(this->Pending.timestep) + ")");
    }
    if (this->Frames.empty())
    {
      throw ParseError{ "the file contains no snapshot ('ITEM: TIMESTEP' ... 'ITEM: ATOMS')" };
    }
  }

private:
  /// A line between atom blocks: blank, or an "ITEM:" header.
  bool indexLine(std::string_view line)
  {
    const std::string_view text = trim(line);
    const std::uint64_t lineNumber = this->Reader.lineNumber();
    if (text.empty())
    {
      return true; // tolerated between sections
    }
    if (text.find('\0') != std::string_view::npos)
    {
      throw ParseError{ where(lineNumber) +
                        " holds NUL bytes: binary data, not text (a crash can leave zeros at "
                        "the end of a file)" };
    }
    if (this->Reader.lastLineUnterminated())
    {
      // LAMMPS ends every line with a newline: a header line without one was cut short.
      return this->truncated(
        "the file ends in the middle of " + where(lineNumber) + " (" + quote(text) + ")");
    }
    if (!startsWith(text, "ITEM:"))
    {
      throw ParseError{ where(lineNumber) + ": expected an 'ITEM:' header, found " + quote(text) +
                        (!this->InHeader && !this->Frames.empty()
                            ? " (are there more atom lines than NUMBER OF ATOMS says?)"
                            : "") };
    }
    return this->readSection(trim(text.substr(5)), text, lineNumber);
  }

  /// The section an "ITEM: <item>" header (the whole line: text) starts.
  bool readSection(std::string_view item, std::string_view text, std::uint64_t lineNumber)
  {
    if (item == "UNITS" || item == "TIME" || item == "TIMESTEP" || item == "NUMBER OF ATOMS")
    {
      return this->readValueItem(item, lineNumber);
    }
    if (startsWith(item, "BOX BOUNDS"))
    {
      return this->readBox(item, lineNumber);
    }
    if (item == "ATOMS" || startsWith(item, "ATOMS ") || startsWith(item, "ATOMS\t"))
    {
      return this->readAtoms(item, lineNumber);
    }
    if (item == "NUMBER OF ENTRIES" || startsWith(item, "ENTRIES"))
    {
      throw ParseError{
        where(lineNumber) + ": " + quote(text) +
        " belongs to a 'dump local' file (per-bond or per-pair values), not to a per-atom "
        "dump"
      };
    }
    if (startsWith(item, "DIMENSION") || startsWith(item, "GRID"))
    {
      throw ParseError{ where(lineNumber) + ": " + quote(text) +
                        " belongs to a 'dump grid' file, not to a per-atom dump" };
    }
    throw ParseError{ where(lineNumber) + ": unknown section " + quote(text) +
                      " (expected TIMESTEP, NUMBER OF ATOMS, BOX BOUNDS, ATOMS, TIME or UNITS)" };
  }

  /// A snapshot that stops short: an error if no snapshot is complete, else a warning and
  /// the end of the index (the complete snapshots stay). Returns false: indexing stops.
  bool truncated(const std::string& message)
  {
    if (this->Frames.empty())
    {
      throw ParseError{ message };
    }
    this->Warnings.push_back(
      "'" + this->FileName + "': " + message + "; this incomplete snapshot is ignored");
    return false;
  }

  /// UNITS, TIME and TIMESTEP may start a snapshot; a second TIMESTEP before ATOMS is damage.
  void beginHeader(std::uint64_t line)
  {
    if (this->HasTimestep)
    {
      throw ParseError{ where(line) + ": a new snapshot starts, but the one at " +
                        where(this->Pending.headerLine) + " (timestep " +
                        std::to_string(this->Pending.timestep) + ") has no 'ITEM: ATOMS' section" };
    }
    if (!this->InHeader)
    {
      this->InHeader = true;
      this->Pending = DumpFrameInfo();
      this->Pending.headerLine = line;
      this->Pending.units = this->Units;
    }
  }

  /// The items whose value is the one line under them: UNITS (dump_modify units yes, written
  /// once and carried to later snapshots), TIME (dump_modify time yes), TIMESTEP, NUMBER OF
  /// ATOMS. False if the file ends before the value.
  bool readValueItem(std::string_view item, std::uint64_t lineNumber)
  {
    const bool count = item == "NUMBER OF ATOMS";
    if (count && !this->HasTimestep)
    {
      throw ParseError{ where(lineNumber) + ": 'ITEM: NUMBER OF ATOMS' before 'ITEM: "
                                            "TIMESTEP'" };
    }
    if (!count)
    {
      this->beginHeader(lineNumber);
    }
    std::string_view line;
    if (!this->Reader.next(line))
    {
      return this->truncated("the file ends after 'ITEM: " + std::string(item) + "' at " +
                             where(this->Reader.lineNumber()));
    }
    const std::string_view value = trim(line);
    DumpFrameInfo& pending = this->Pending;
    if (item == "UNITS")
    {
      this->Units = std::string(value);
      pending.units = this->Units;
    }
    else if (item == "TIME")
    {
      expectValue(parseDouble(value, pending.time), lineNumber + 1, "the simulation time", value);
      pending.hasTime = true;
    }
    else if (item == "TIMESTEP")
    {
      expectValue(
        parseInt64(value, pending.timestep), lineNumber + 1, "an integer timestep", value);
      this->HasTimestep = true;
    }
    else
    {
      expectValue(parseInt64(value, pending.numberOfAtoms) && pending.numberOfAtoms >= 0,
        lineNumber + 1,
        "a number of atoms >= 0",
        value);
      this->HasCount = true;
    }
    return true;
  }

  /// "ITEM: BOX BOUNDS <flags>" and its three lines; a file that ends inside them cuts the
  /// snapshot short.
  bool readBox(std::string_view item, std::uint64_t lineNumber)
  {
    if (!this->HasTimestep)
    {
      throw ParseError{ where(lineNumber) + ": 'ITEM: BOX BOUNDS' before 'ITEM: TIMESTEP'" };
    }
    try
    {
      parseBox(item.substr(10), this->Reader, this->Pending.box);
    }
    catch (const ParseError& e)
    {
      if (startsWith(e.message, "the file ends"))
      {
        return this->truncated(e.message);
      }
      throw;
    }
    return true;
  }

  /// "ITEM: ATOMS <names>": the column names, then the extent of the atom block, which
  /// completes the snapshot.
  bool readAtoms(std::string_view item, std::uint64_t lineNumber)
  {
    if (!this->HasTimestep || !this->HasCount)
    {
      throw ParseError{ where(lineNumber) + ": 'ITEM: ATOMS' before " +
                        (this->HasTimestep ? "'ITEM: NUMBER OF ATOMS'" : "'ITEM: TIMESTEP'") };
    }
    for (std::string_view name : splitTokens(item.substr(5)))
    {
      this->Pending.columnNames.emplace_back(name);
    }
    this->Pending.atomsOffset = this->Reader.offset();
    this->Pending.atomsLine = lineNumber + 1;
    const std::uint64_t count = static_cast<std::uint64_t>(this->Pending.numberOfAtoms);
    const std::uint64_t found = this->inferLegacyColumns(count, lineNumber);
    const std::string beyond = atomCountBeyondFile(count,
      this->FileSize - std::min(this->FileSize, std::uintmax_t(this->Pending.atomsOffset)),
      lineNumber);
    if (!beyond.empty())
    {
      return this->truncated(describeFrame(this->Frames.size(), this->Pending) + ": " + beyond);
    }
    const std::uint64_t complete = this->skipAtomLines(count, found);
    if (complete != count && this->Reader.atHeader())
    {
      return this->dropShortSnapshot(complete, count);
    }
    if (complete != count)
    {
      return this->truncated(describeFrame(this->Frames.size(), this->Pending) +
                             " is truncated: it has " + std::to_string(count) +
                             " atoms, the file ends after " + std::to_string(complete) +
                             " complete atom lines");
    }
    this->Frames.push_back(this->Pending);
    this->endSnapshot();
    return true;
  }

  /// The next snapshot's header items start afresh.
  void endSnapshot()
  {
    this->InHeader = false;
    this->HasTimestep = false;
    this->HasCount = false;
  }

  /// An atom block that an "ITEM:" header ends before NUMBER OF ATOMS lines: which atoms
  /// are missing cannot be told, so the snapshot is dropped with a warning, and indexing goes
  /// on at that header (the snapshots after it are intact).
  bool dropShortSnapshot(std::uint64_t complete, std::uint64_t count)
  {
    this->Warnings.push_back(
      "'" + this->FileName + "': " + describeFrame(this->Frames.size(), this->Pending) +
      " has only " + std::to_string(complete) + " of its " + std::to_string(count) +
      " atom lines before the 'ITEM:' header at " + where(this->Reader.lineNumber() + 1) +
      "; this incomplete snapshot is ignored");
    this->endSnapshot();
    return true;
  }

  /// Old "dump atom" output has "ITEM: ATOMS" without names: the fixed columns follow from
  /// the first atom line's number of values. Returns the atom lines read (0 or 1).
  std::uint64_t inferLegacyColumns(std::uint64_t count, std::uint64_t lineNumber)
  {
    std::vector<std::string>& names = this->Pending.columnNames;
    if (!names.empty())
    {
      return 0;
    }
    if (count == 0)
    {
      legacyAtomColumns(5, names);
      return 0;
    }
    std::string_view first;
    if (!this->Reader.next(first))
    {
      return 0; // the file ends here: the count of the atom lines says so
    }
    const std::size_t values = splitTokens(first).size();
    if (!legacyAtomColumns(values, names))
    {
      throw ParseError{ where(lineNumber) + ": 'ITEM: ATOMS' has no column names, and " +
                        std::to_string(values) +
                        " values per line do not match the old 'dump atom' layout" };
    }
    return 1;
  }

  /// Skips the atom block after its first `found` lines; returns its complete atom lines.
  std::uint64_t skipAtomLines(std::uint64_t count, std::uint64_t found)
  {
    found += this->Reader.skipLines(count - found);
    if (!this->Reader.lastLineUnterminated())
    {
      return found;
    }
    // LAMMPS ends every line with a newline, so the file was cut in this line (a simulation
    // killed while writing) or written by hand. As the last atom line it is kept if it has
    // all its values, well formed, but its last value may have lost digits; otherwise it is
    // not a complete line.
    const std::string last = readLastLine(this->FileName, this->Reader.lastLineOffset());
    const std::vector<std::string_view> values = splitTokens(last);
    if (found != count || !isCompleteAtomLine(values, this->Pending.columnNames))
    {
      return found - 1;
    }
    this->Warnings.push_back("'" + this->FileName + "': the file ends without a newline in " +
                             where(this->Reader.lineNumber()) + ", the last atom line of " +
                             describeFrame(this->Frames.size(), this->Pending) +
                             ": it is kept, but its last value " + quote(values.back()) +
                             " may have been cut short");
    return found;
  }

  const std::string& FileName;
  const std::uintmax_t FileSize;
  LineReader& Reader;
  std::vector<DumpFrameInfo>& Frames;
  std::vector<std::string>& Warnings;
  /// The header items of the snapshot being read; it is complete at its ATOMS section.
  DumpFrameInfo Pending;
  bool InHeader = false;
  bool HasTimestep = false;
  bool HasCount = false;
  std::string Units;
};

/// What a column of a snapshot becomes.
enum class Role
{
  Id,
  Type,
  Position,
  Number,
  Text,
};

/// Every column's role and array: Slots[c] is its index in DumpFrame::Columns or
/// TextColumns, or the component k of a position column.
struct ColumnPlan
{
  std::vector<Role> roles;
  std::vector<int> slots;
  std::vector<std::string> arrayNames;
};

/// Index of the first column named `name`, or -1.
std::ptrdiff_t columnIndex(const std::vector<std::string>& names, const char* name)
{
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : it - names.begin();
}

/// Chooses the coordinate triple: x y z, else xu yu zu, else xs ys zs, else xsu ysu zsu.
/// Sets frame.positions and frame.positionColumns, and the triple's columns.
void choosePositions(const DumpFrameInfo& info, DumpFrame& frame, std::ptrdiff_t columns[3])
{
  struct Family
  {
    PositionSource source;
    const char* names[3];
  };
  const Family families[] = {
    { PositionSource::Wrapped, { "x", "y", "z" } },
    { PositionSource::Unwrapped, { "xu", "yu", "zu" } },
    { PositionSource::Scaled, { "xs", "ys", "zs" } },
    { PositionSource::ScaledUnwrapped, { "xsu", "ysu", "zsu" } },
  };
  std::string partial;
  for (const Family& family : families)
  {
    std::ptrdiff_t c[3];
    int have = 0;
    for (int k = 0; k < 3; ++k)
    {
      c[k] = columnIndex(info.columnNames, family.names[k]);
      have += c[k] >= 0 ? 1 : 0;
    }
    if (have == 3)
    {
      frame.positions = family.source;
      for (int k = 0; k < 3; ++k)
      {
        columns[k] = c[k];
        frame.positionColumns[k] = family.names[k];
      }
      return;
    }
    if (have > 0 && partial.empty())
    {
      partial = std::string(" (it has only part of ") + family.names[0] + " " + family.names[1] +
                " " + family.names[2] + ")";
    }
  }
  throw ParseError{ "no atom coordinates: the columns are '" + joinNames(info.columnNames) +
                    "', one of x y z, xu yu zu, xs ys zs or xsu ysu zsu is needed" + partial };
}

/// Roles from the column names; repeated names get a suffix so arrays stay distinct. The
/// kinds of the ordinary columns (number or text) are decided by the first atom line.
ColumnPlan planColumns(const std::vector<std::string>& names, const std::ptrdiff_t positions[3])
{
  const std::size_t columnCount = names.size();
  ColumnPlan plan{ std::vector<Role>(columnCount, Role::Number),
    std::vector<int>(columnCount, -1),
    std::vector<std::string>(columnCount) };
  std::unordered_map<std::string, int> seenNames;
  for (std::size_t c = 0; c < columnCount; ++c)
  {
    const int seen = seenNames[names[c]]++;
    plan.arrayNames[c] = seen ? names[c] + "_" + std::to_string(seen + 1) : names[c];
    if (seen)
    {
      continue; // a repeated id/type/position column is kept as an ordinary array
    }
    if (names[c] == "id")
    {
      plan.roles[c] = Role::Id;
    }
    else if (names[c] == "type")
    {
      plan.roles[c] = Role::Type;
    }
    else if (names[c] == "element" || names[c] == "typelabel")
    {
      plan.roles[c] = Role::Text;
    }
  }
  for (int k = 0; k < 3; ++k)
  {
    plan.roles[positions[k]] = Role::Position;
    plan.slots[positions[k]] = k;
  }
  return plan;
}

/// The arrays of positions, ids and types for `count` atoms.
void allocateFrame(std::size_t count, const std::vector<std::string>& names, DumpFrame& frame)
{
  frame.numberOfAtoms = count;
  frame.points.assign(3 * count, 0.0);
  frame.hasIds = columnIndex(names, "id") >= 0;
  frame.hasTypes = columnIndex(names, "type") >= 0;
  if (frame.hasIds)
  {
    frame.ids.resize(count);
  }
  if (frame.hasTypes)
  {
    frame.types.resize(count);
  }
}

/// The values of an atom line into tokens, which has one per column; throws if the line
/// has more or fewer.
void splitAtomLine(std::string_view line,
  std::uint64_t lineNumber,
  const std::vector<std::string>& names,
  std::vector<std::string_view>& tokens)
{
  const std::size_t columnCount = names.size();
  std::string_view rest = line;
  std::size_t found = 0;
  std::string_view token;
  while (found <= columnCount && nextToken(rest, token))
  {
    if (found < columnCount)
    {
      tokens[found] = token;
    }
    ++found;
  }
  if (found != columnCount)
  {
    throw ParseError{ where(lineNumber) + ": expected " + std::to_string(columnCount) +
                      " values (" + joinNames(names) + "), found " +
                      std::to_string(splitTokens(line).size()) };
  }
}

/// Decides each remaining column's kind from its first value (the first atom line's
/// tokens): numbers become double arrays, anything else (names, labels) text arrays; and
/// makes the arrays for `count` atoms.
void chooseColumnKinds(const std::vector<std::string_view>& tokens,
  std::size_t count,
  ColumnPlan& plan,
  DumpFrame& frame)
{
  for (std::size_t c = 0; c < tokens.size(); ++c)
  {
    Role& role = plan.roles[c];
    double probe;
    std::int64_t integer;
    if (role == Role::Number && !parseDouble(tokens[c], probe))
    {
      role = Role::Text;
    }
    if (role == Role::Type && !parseInt64(tokens[c], integer))
    {
      // Type labels written in place of numeric types ("C1", "Ow"): keep them as text.
      role = Role::Text;
      frame.hasTypes = false;
      frame.types.clear();
    }
    if (role == Role::Number)
    {
      plan.slots[c] = static_cast<int>(frame.columns.size());
      frame.columns.push_back({ plan.arrayNames[c], std::vector<double>(count) });
    }
    else if (role == Role::Text)
    {
      plan.slots[c] = static_cast<int>(frame.textColumns.size());
      frame.textColumns.push_back({ plan.arrayNames[c], std::vector<std::string>(count) });
    }
  }
}

/// Converts atom a's values (tokens, of line lineNumber) into the frame's arrays; throws at
/// the first value that is not what its column holds.
void storeAtomValues(const std::vector<std::string_view>& tokens,
  std::size_t a,
  std::uint64_t lineNumber,
  const std::vector<std::string>& names,
  const ColumnPlan& plan,
  DumpFrame& frame)
{
  for (std::size_t c = 0; c < tokens.size(); ++c)
  {
    const std::string_view t = tokens[c];
    const int slot = plan.slots[c];
    bool ok = true;
    switch (plan.roles[c])
    {
      case Role::Id:
        ok = parseInt64(t, frame.ids[a]);
        break;
      case Role::Type:
      {
        std::int64_t type = 0;
        ok = parseInt64(t, type) && type >= std::numeric_limits<std::int32_t>::min() &&
             type <= std::numeric_limits<std::int32_t>::max();
        frame.types[a] = static_cast<std::int32_t>(type);
        break;
      }
      case Role::Position:
        ok = parseDouble(t, frame.points[3 * a + slot]);
        break;
      case Role::Number:
        ok = parseDouble(t, frame.columns[slot].values[a]);
        break;
      case Role::Text:
        frame.textColumns[slot].values[a] = std::string(t);
        break;
    }
    if (!ok)
    {
      const bool integer = plan.roles[c] == Role::Id || plan.roles[c] == Role::Type;
      throw ParseError{ where(lineNumber) + ", column '" + names[c] + "': " + quote(t) +
                        " is not " + (integer ? "an integer" : "a number") };
    }
  }
}

/// Reads the snapshot's atom lines into the frame's arrays (allocated for them).
void readAtomLines(const std::string& fileName,
  const DumpFrameInfo& info,
  ColumnPlan& plan,
  DumpFrame& frame)
{
  const std::size_t count = frame.numberOfAtoms;
  LineReader reader;
  if (count > 0 && !reader.open(fileName, info.atomsOffset, info.atomsLine - 1))
  {
    throw ParseError{ "cannot open the file again: " + std::string(std::strerror(errno)) };
  }
  std::vector<std::string_view> tokens(info.columnNames.size());
  std::string_view line;
  for (std::size_t a = 0; a < count; ++a)
  {
    if (!reader.next(line))
    {
      throw ParseError{ "the file ends after " + std::to_string(a) + " of " +
                        std::to_string(count) +
                        " atom lines (did it change since it was opened?)" };
    }
    splitAtomLine(line, reader.lineNumber(), info.columnNames, tokens);
    if (a == 0)
    {
      chooseColumnKinds(tokens, count, plan, frame);
    }
    storeAtomValues(tokens, a, reader.lineNumber(), info.columnNames, plan, frame);
  }
}

/// No atom line to look at: every ordinary column becomes an empty numeric array, so a
/// snapshot where all atoms left still has the same arrays as the others.
void addEmptyColumns(const ColumnPlan& plan, DumpFrame& frame)
{
  for (std::size_t c = 0; c < plan.roles.size(); ++c)
  {
    if (plan.roles[c] == Role::Number)
    {
      frame.columns.push_back({ plan.arrayNames[c], std::vector<double>() });
    }
    else if (plan.roles[c] == Role::Text)
    {
      frame.textColumns.push_back({ plan.arrayNames[c], std::vector<std::string>() });
    }
  }
}

/// Scaled coordinates s to Cartesian: r = origin + s0 A + s1 B + s2 C.
void convertScaledPositions(const DumpBox& box, DumpFrame& frame)
{
  for (std::size_t a = 0; a < frame.numberOfAtoms; ++a)
  {
    const double s[3] = { frame.points[3 * a], frame.points[3 * a + 1], frame.points[3 * a + 2] };
    box.scaledToCartesian(s, &frame.points[3 * a]);
  }
}

/// LAMMPS writes atoms in the order processors own them; sorting by id keeps an atom's
/// index from one snapshot to the next (when no atom is lost or created). Atoms with the same
/// id keep their file order (stable sort).
void sortById(DumpFrame& frame)
{
  if (!frame.hasIds || std::is_sorted(frame.ids.begin(), frame.ids.end()))
  {
    return;
  }
  const std::size_t count = frame.numberOfAtoms;
  std::vector<std::size_t> order(count);
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(),
    order.end(),
    [&](std::size_t i, std::size_t j) { return frame.ids[i] < frame.ids[j]; });
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
  permute(frame.ids, 1);
  permute(frame.points, 3);
  if (frame.hasTypes)
  {
    permute(frame.types, 1);
  }
  for (DumpColumn& column : frame.columns)
  {
    permute(column.values, 1);
  }
  for (DumpTextColumn& column : frame.textColumns)
  {
    permute(column.values, 1);
  }
}

/// Reads the atoms of the snapshot `info` into frame: chooses the coordinates and every
/// column's role, reads the atom lines, converts scaled coordinates, sorts by id.
void readSnapshot(const std::string& fileName, const DumpFrameInfo& info, DumpFrame& frame)
{
  std::ptrdiff_t positions[3] = { -1, -1, -1 };
  choosePositions(info, frame, positions);
  const bool scaled =
    frame.positions == PositionSource::Scaled || frame.positions == PositionSource::ScaledUnwrapped;
  if (scaled && !info.box.present)
  {
    throw ParseError{ "scaled coordinates (" + frame.positionColumns[0] +
                      " ...) need the box, and the snapshot has no 'ITEM: BOX BOUNDS'" };
  }
  ColumnPlan plan = planColumns(info.columnNames, positions);
  allocateFrame(static_cast<std::size_t>(info.numberOfAtoms), info.columnNames, frame);
  readAtomLines(fileName, info, plan, frame);
  if (frame.numberOfAtoms == 0)
  {
    addEmptyColumns(plan, frame);
  }
  if (scaled)
  {
    convertScaledPositions(info.box, frame);
  }
  sortById(frame);
}

} // namespace

//------------------------------------------------------------------------------
bool DumpBox::isPeriodic(int axis) const
{
  return axis >= 0 && axis < 3 && this->boundary[axis] == "pp";
}

void DumpBox::scaledToCartesian(const double s[3], double r[3]) const
{
  for (int k = 0; k < 3; ++k)
  {
    r[k] = this->origin[k] + s[0] * this->A[k] + s[1] * this->B[k] + s[2] * this->C[k];
  }
}

void DumpBox::bounds(double bounds[6]) const
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
    this->scaledToCartesian(s, r);
    for (int k = 0; k < 3; ++k)
    {
      bounds[2 * k] = std::min(bounds[2 * k], r[k]);
      bounds[2 * k + 1] = std::max(bounds[2 * k + 1], r[k]);
    }
  }
}

void DumpFrame::clear()
{
  *this = DumpFrame();
}

//------------------------------------------------------------------------------
TimeTable buildTimeTable(const std::vector<DumpFrameInfo>& frames)
{
  std::vector<std::size_t> order(frames.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(),
    order.end(),
    [&](std::size_t a, std::size_t b) { return frames[a].timestep < frames[b].timestep; });
  TimeTable table;
  for (std::size_t i : order)
  {
    const double t = static_cast<double>(frames[i].timestep);
    if (!table.times.empty() && table.times.back() == t)
    {
      table.frames.back() = i; // same timestep again: the later snapshot wins
    }
    else
    {
      table.times.push_back(t);
      table.frames.push_back(i);
    }
  }
  return table;
}

std::size_t TimeTable::frameForTime(double t) const
{
  if (this->times.empty() || std::isnan(t))
  {
    return this->frames.empty() ? 0 : this->frames.front();
  }
  const double tolerance = 1e-9 * std::max(1.0, std::fabs(t));
  const auto it = std::upper_bound(this->times.begin(), this->times.end(), t + tolerance);
  const std::size_t index = it == this->times.begin() ? 0 : (it - this->times.begin()) - 1;
  return this->frames[index];
}

//------------------------------------------------------------------------------
bool DumpParser::fail(const std::string& message)
{
  this->Error = message;
  return false;
}

void DumpParser::close()
{
  this->FileName.clear();
  this->Error.clear();
  this->Warnings.clear();
  this->Frames.clear();
  this->FileSize = 0;
  this->FileTime = 0;
}

bool DumpParser::isStale() const
{
  if (this->FileName.empty())
  {
    return false;
  }
  // A file that is missing (size -1) stays missing until it appears: open() failed for it and
  // would fail the same way again.
  std::error_code ec;
  return std::filesystem::file_size(this->FileName, ec) != this->FileSize ||
         fileTimeOf(this->FileName) != this->FileTime;
}

bool DumpParser::looksLikeDump(const std::string& fileName)
{
  std::error_code ec;
  if (!std::filesystem::is_regular_file(fileName, ec))
  {
    return false;
  }
  const std::string head = readHead(fileName, 4096);
  return !head.empty() && sniffNotADump(fileName, head).empty() &&
         head.find("ITEM:") != std::string::npos;
}

bool DumpParser::open(const std::string& fileName)
{
  this->close();
  this->FileName = fileName;
  try
  {
    // What IsStale compares with: the size is -1 for a missing file or a directory.
    std::error_code ec;
    this->FileSize = std::filesystem::file_size(fileName, ec);
    this->FileTime = fileTimeOf(fileName);
    LineReader reader;
    const std::string unreadable = checkFile(fileName, this->FileSize, reader);
    if (!unreadable.empty())
    {
      return this->fail(unreadable);
    }
    SnapshotIndexer(fileName, this->FileSize, reader, this->Frames, this->Warnings).run();
  }
  catch (const ParseError& e)
  {
    if (!this->Frames.empty())
    {
      // Damage after complete snapshots: keep those (the index of anything after the damage
      // cannot be trusted) and say where the file stops being readable.
      this->Warnings.push_back("'" + fileName + "': " + e.message + "; the rest of the file (" +
                               "after snapshot " + std::to_string(this->Frames.size()) +
                               ") is ignored");
      return true;
    }
    this->Frames.clear();
    return this->fail("'" + fileName + "': " + e.message);
  }
  catch (const std::bad_alloc&)
  {
    this->Frames.clear();
    return this->fail("'" + fileName + "': out of memory while indexing the file");
  }
  catch (const std::exception& e)
  {
    this->Frames.clear();
    return this->fail("'" + fileName + "': " + e.what());
  }
  return true;
}

bool DumpParser::readFrame(std::size_t index, DumpFrame& frame)
{
  frame.clear();
  if (index >= this->Frames.size())
  {
    return this->fail("snapshot " + std::to_string(index + 1) + " requested, the file has " +
                      std::to_string(this->Frames.size()));
  }
  const DumpFrameInfo& info = this->Frames[index];
  frame.info = info;
  const std::string where = "'" + this->FileName + "', " + describeFrame(index, info);
  try
  {
    readSnapshot(this->FileName, info, frame);
    const std::string repeated = frame.hasIds ? describeRepeatedIds(frame.ids) : std::string();
    if (!repeated.empty())
    {
      frame.warnings.push_back(where + ": " + repeated);
    }
  }
  catch (const ParseError& e)
  {
    frame.clear();
    return this->fail(where + ": " + e.message);
  }
  catch (const std::bad_alloc&)
  {
    frame.clear();
    return this->fail(where + ": out of memory for " + std::to_string(info.numberOfAtoms) +
                      " atoms x " + std::to_string(info.columnNames.size()) + " columns");
  }
  catch (const std::exception& e)
  {
    frame.clear();
    return this->fail(where + ": " + e.what());
  }
  return true;
}

} // namespace lammps
} // namespace raymappers
