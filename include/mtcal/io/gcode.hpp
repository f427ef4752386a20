// G-code reader: the RS274 subset of straight and circular moves (G0 G1 G2 G3), planes, units and distance modes.
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

  bool is_arc() const { return motion == GcodeMotion::ArcCW || motion == GcodeMotion::ArcCCW; }
};

struct GcodeOptions {
  // Axis letters the machine has (any order, e.g. "XYZBC"); a word for another axis is an error.
  std::string axes = "XYZABC";
  // Position before the first move, program coordinates (mm, deg).
  GcodePosition start{};
};

// Arc end-radius tolerance: |r_start - r_end| may be max(kArcRadiusTolerance, kArcRadiusRelative
// r); R may be shorter than half the chord by as much before it is an error.
inline constexpr double kArcRadiusTolerance = 0.002;  // mm
inline constexpr double kArcRadiusRelative = 1e-4;

struct GcodeCounts {
  std::size_t lines = 0;          // lines read
  std::size_t blocks = 0;         // lines with at least one word
  std::size_t moves = 0;          // blocks that move
  std::size_t ignored_words = 0;  // S, T, M words and the no-op G40 G49 G80 G94
};

// Streaming reader over the text (which must outlive it): one move at a time, so that a program
// of any length is read in constant memory. Every error is an InputError with the source name
// and line, and the column in its message ("column 7: ...").
class GcodeReader {
 public:
  GcodeReader(std::string_view text, std::string source, GcodeOptions options = {});
  // The next block that moves; false at the end of the program.
  bool next(GcodeMove& move);
  const GcodeCounts& counts() const { return counts_; }
  const std::string& source() const { return source_; }

 private:
  struct Word {
    char letter;
    double value;
    int column;
  };
  bool read_block();  // words of the next line with any, into words_; false at the end
  [[noreturn]] void fail(int column, const std::string& what) const;
  bool apply_block(GcodeMove& move);

  std::string_view text_;
  std::string source_;
  GcodeOptions options_;
  std::array<bool, 26> allowed_{};
  std::size_t pos_ = 0;
  int line_ = 0;
  bool opened_ = false;  // a leading % was read
  bool closed_ = false;  // a trailing % was read
  std::vector<Word> words_;
  GcodeCounts counts_;
  // Modal state.
  int motion_ = -1;  // 0 1 2 3 or -1 before any motion code
  GcodePlane plane_ = GcodePlane::XY;
  bool incremental_ = false;
  bool inches_ = false;
  double feed_ = 0;
  GcodePosition position_{};
};

struct GcodeProgram {
  std::string source;
  std::vector<GcodeMove> moves;
  GcodeCounts counts;
};

// The whole program at once (a million blocks take about 200 MB; use GcodeReader to stream).
GcodeProgram parse_gcode(std::string_view text, const std::string& source, const GcodeOptions& options = {});
GcodeProgram read_gcode(const std::string& path, const GcodeOptions& options = {});

// Path length of a move: the straight or helical length in X Y Z (mm); 0 for a rotary-only move.
double path_length(const GcodeMove& move);
// Program position at progress t in [0, 1] of a move (t = 1 gives end exactly).
GcodePosition position_at(const GcodeMove& move, double t);

}  // namespace mtcal
