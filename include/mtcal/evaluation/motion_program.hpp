// Motion programs as records: the moves of a G-code program (straight lines, arcs and helices in program coordinates).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace mtcal {

enum class GcodeMotion : std::uint8_t { Rapid, Linear, ArcCW, ArcCCW };
// G17 (X, Y; normal Z), G18 (Z, X; normal Y), G19 (Y, Z; normal X), as RS274NGC orders them so
// that the first axis x the second is the normal and G3 turns positively about it.
enum class GcodePlane : std::uint8_t { XY, ZX, YZ };

std::string_view to_string(GcodeMotion m);  // "rapid" "linear" "arc_cw" "arc_ccw"
std::string_view to_string(GcodePlane p);   // "G17" "G18" "G19"

// Program axes in this fixed order; positions in mm (X Y Z) and deg (A B C).
inline constexpr char kGcodeAxes[6] = {'X', 'Y', 'Z', 'A', 'B', 'C'};
using GcodePosition = std::array<double, 6>;

// Indices into GcodePosition of a plane's first, second and normal axis.
struct PlaneAxes {
  int u, v, w;
};
PlaneAxes plane_axes(GcodePlane p);

// One block that moves, in program coordinates, always mm and deg whatever G20/G21 was.
struct GcodeMove {
  GcodeMotion motion = GcodeMotion::Linear;
  GcodePlane plane = GcodePlane::XY;  // the plane in effect (used by arcs)
  int line = 0;                       // 1-based source line
  std::int64_t n = -1;                // N word, -1 if none
  double feed = 0;                    // mm/min; 0 until an F word
  GcodePosition start{}, end{};
  // Arcs only: centre (the normal coordinate is the start's), signed sweep in rad (positive
  // turns positively about the plane's normal: G3; +-2 pi for a full circle). The radius goes
  // linearly from |start - centre| to |end - centre| in the plane (they agree within the
  // tolerance), the normal axis and A B C linearly with the angle: a helix.
  std::array<double, 3> centre{};
  double sweep = 0;
  // The tool in the spindle (the T of the last tool change, M6; -1 before any) and the spindle
  // speed programmed (S, rpm; 0 before any): kept so that a caller can tell the tools apart.
  int tool = -1;
  double spindle = 0;
  // The move's index among the moves of its block: 0 for the first; a canned cycle, G28/G30 and
  // G53 give a block several moves, or moves whose coordinates are not the block's words.
  int part = 0;

  bool is_arc() const { return motion == GcodeMotion::ArcCW || motion == GcodeMotion::ArcCCW; }
};

struct GcodeCounts {
  std::size_t lines = 0;          // lines read
  std::size_t blocks = 0;         // lines with at least one word
  std::size_t moves = 0;          // blocks that move
  std::size_t ignored_words = 0;  // S, T, M words and the G words that move nothing (G40 G49 G80 G94 G61 G64 ...)
  std::size_t m_words = 0, s_words = 0, t_words = 0;  // of them: M, S and T words kept (tool, spindle)
  std::size_t tool_changes = 0;                       // M6
  std::size_t cycles = 0;                             // canned cycle holes expanded (G73 G81-G89)
  std::size_t expanded_blocks = 0;  // blocks whose moves are not their own words: cycles, G28/G30, G53
  std::size_t offset_blocks = 0;    // blocks that moved under a work offset or tool length other than 0
  std::size_t warnings = 0;         // words not simulated, each named in a warning
};

// A program read whole.
struct GcodeProgram {
  std::string source;
  std::vector<GcodeMove> moves;
  GcodeCounts counts;
  // What was read but not simulated, each "file:line: column c: word ...: why" (the first 100).
  std::vector<std::string> warnings;
  // Which reader gave the moves: "mtcal" (the ISO dialect) or "rs274" (LinuxCNC's interpreter).
  std::string interpreter = "mtcal";
};

// Moves one at a time, so that a program of any length is processed in constant memory (the
// formats layer's G-code reader is one).
class MoveSource {
 public:
  virtual ~MoveSource() = default;
  // The next block that moves; false at the end of the program.
  virtual bool next(GcodeMove& move) = 0;
  // Counts of what was read so far.
  virtual const GcodeCounts& counts() const = 0;
  // The program's name in messages (a file name).
  virtual const std::string& source() const = 0;
  // Words read but not simulated so far, each naming its file, line and word (the first 100).
  virtual const std::vector<std::string>& warnings() const = 0;
};

// Path length of a move: the straight or helical length in X Y Z (mm); 0 for a rotary-only move.
double path_length(const GcodeMove& move);
// Program position at progress t in [0, 1] of a move (t = 1 gives end exactly).
GcodePosition position_at(const GcodeMove& move, double t);

}  // namespace mtcal
