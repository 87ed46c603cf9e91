// seam: reading and validating triangle meshes and polylines, writing results atomically.
//
// The readers are hand-written (OFF, OBJ, STL, PLY) so that every error names the file and the
// precise problem, and so that no input, however broken, can crash, hang or make them allocate
// more memory than the file's size justifies: every count read from a file is capped by the
// number of bytes left before memory is reserved for it.
//
// Numbering in messages: vertices and faces are numbered from 0 in the order of the file (the
// indices of the resulting TriangleSoup); vertex indices are quoted as written in the file
// (1-based for OBJ). Syntax errors also give the 1-based line number.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/io.h>
#include <seam/kernels.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <locale>
#include <map>
#include <mutex>
#include <sstream>
#include <string_view>
#include <stdexcept>
#include <system_error>
#include <unordered_map>
#include <utility>

#include <fcntl.h>
#include <locale.h>  // newlocale, strtod_l (POSIX / glibc)
#include <sys/stat.h>
#include <unistd.h>

namespace seam {

namespace {

namespace fs = std::filesystem;

// ------------------------------------------------------------------ messages

[[noreturn]] void invalid(const std::string& name, const std::string& what) {
  throw InvalidInput(name + ": " + what);
}

std::string errno_text(int e) {
  return e != 0 ? std::generic_category().message(e) : std::string("unknown error");
}

/// A piece of the file quoted in a one-line message: at most 40 characters, control and
/// non-ASCII bytes shown as \xNN.
std::string quote(std::string_view s) {
  constexpr std::size_t max_chars = 40;
  std::string out = "'";
  const std::size_t n = std::min(s.size(), max_chars);
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      static const char hex[] = "0123456789abcdef";
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  if (s.size() > max_chars) out += "...";
  out += "'";
  return out;
}

/// An integral double in full ("-3", "2444444444444444417808384"), without converting it to an
/// integer type that may not hold it (undefined behaviour: found by fuzzing the PLY reader).
std::string integral_text(double v) {
  char buffer[400];
  std::snprintf(buffer, sizeof buffer, "%.0f", v);
  return buffer;
}

std::string line_prefix(std::size_t line) { return "line " + std::to_string(line) + ": "; }

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i])))
      return false;
  return true;
}

// ------------------------------------------------------------------ numbers

/// Parses the whole token as a double, independently of the global locale. Accepts a leading
/// '+', and "inf"/"nan" (the callers reject non-finite values with their own message). A value
/// too large for a double becomes infinite, a value too small becomes 0 or subnormal.
bool parse_double(std::string_view t, double& out) {
  const char* b = t.data();
  const char* e = b + t.size();
  if (b != e && *b == '+') {
    ++b;
    if (b == e || *b == '+' || *b == '-') return false;
  }
  if (b == e) return false;
  const auto r = std::from_chars(b, e, out, std::chars_format::general);
  if (r.ptr != e) return false;
  if (r.ec == std::errc()) return true;
  if (r.ec != std::errc::result_out_of_range) return false;
  // Overflow or underflow: let strtod in the "C" locale round it (HUGE_VAL, 0 or subnormal).
  static const locale_t c_locale = newlocale(LC_ALL_MASK, "C", locale_t(nullptr));
  if (c_locale == locale_t(nullptr)) return false;
  const std::string s(b, e);
  char* end = nullptr;
  out = strtod_l(s.c_str(), &end, c_locale);
  return end == s.c_str() + s.size();
}

/// Parses the whole token as a (possibly signed) decimal integer.
bool parse_integer(std::string_view t, long long& out) {
  const char* b = t.data();
  const char* e = b + t.size();
  if (b != e && *b == '+') {
    ++b;
    if (b == e || *b == '-') return false;
  }
  if (b == e) return false;
  const auto r = std::from_chars(b, e, out, 10);
  return r.ec == std::errc() && r.ptr == e;
}

bool parse_unsigned(std::string_view t, unsigned long long& out) {
  const char* b = t.data();
  const char* e = b + t.size();
  if (b != e && *b == '+') ++b;
  if (b == e || *b == '-') return false;
  const auto r = std::from_chars(b, e, out, 10);
  return r.ec == std::errc() && r.ptr == e;
}

bool finite3(const Point3d& p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

// ------------------------------------------------------------------ text

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

/// Splits a line into whitespace-separated tokens.
void split(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  std::size_t i = 0;
  const std::size_t n = line.size();
  while (i < n) {
    while (i < n && is_space(line[i])) ++i;
    if (i == n) break;
    const std::size_t start = i;
    while (i < n && !is_space(line[i])) ++i;
    tokens.push_back(line.substr(start, i - start));
  }
}

bool is_blank(std::string_view line) {
  for (char c : line)
    if (!is_space(c)) return false;
  return true;
}

/// The lines of a text, with '#' comments (to the end of the line) removed.
class Lines {
 public:
  explicit Lines(std::string_view text, bool strip_comments = true)
      : text_(text), strip_comments_(strip_comments) {}

  /// The next line (without its '\n' and comment); false at the end of the text.
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    std::size_t end = text_.find('\n', pos_);
    if (end == std::string_view::npos) end = text_.size();
    line = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    ++number_;
    if (strip_comments_) {
      const std::size_t hash = line.find('#');
      if (hash != std::string_view::npos) line = line.substr(0, hash);
    }
    return true;
  }

  /// The next line that is not blank once its comment is removed.
  bool next_nonblank(std::string_view& line) {
    while (next(line))
      if (!is_blank(line)) return true;
    return false;
  }

  std::size_t number() const { return number_; }     ///< 1-based number of the last line read
  std::size_t offset() const { return std::min(pos_, text_.size()); }  ///< byte after it

 private:
  std::string_view text_;
  bool strip_comments_;
  std::size_t pos_ = 0;
  std::size_t number_ = 0;
};

/// The text without a UTF-8 byte-order mark at its start (some editors write one; it is not part
/// of the content: before, an OBJ file lost its first vertex to it).
std::string_view skip_bom(std::string_view text) {
  constexpr std::string_view bom = "\xEF\xBB\xBF";
  if (text.substr(0, bom.size()) == bom) text.remove_prefix(bom.size());
  return text;
}

/// A line quoted in a message, without its surrounding blanks.
std::string quote_trimmed(std::string_view line) {
  std::size_t b = 0, e = line.size();
  while (b < e && is_space(line[b])) ++b;
  while (e > b && is_space(line[e - 1])) --e;
  return quote(line.substr(b, e - b));
}

void reject_binary(std::string_view text, const std::string& name, const char* format) {
  if (text.find('\0') != std::string_view::npos)
    invalid(name, std::string("file contains binary data (not a text ") + format + " file)");
}

// ------------------------------------------------------------------ files

std::string read_file(const std::string& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!ec) {
    if (fs::is_directory(st)) throw IOError(path + ": is a directory");
    if (fs::exists(st) && !fs::is_regular_file(st)) throw IOError(path + ": is not a regular file");
  }
  errno = 0;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) throw IOError(path + ": cannot open file (" + errno_text(errno) + ")");
  std::string data;
  // Reserved at the file's size: grown by doubling, a 258 MB file took a 512 MB string, and
  // 768 MB while the last growth copied it (issue 22, class 8). Read straight into it.
  struct stat file_stat {};
  if (::fstat(::fileno(f), &file_stat) == 0 && S_ISREG(file_stat.st_mode) && file_stat.st_size > 0)
    data.reserve(static_cast<std::size_t>(file_stat.st_size) + 1);
  for (;;) {
    const std::size_t old_size = data.size();
    const std::size_t chunk = std::max<std::size_t>(data.capacity() - old_size, 1 << 16);
    data.resize(old_size + chunk);
    const std::size_t got = std::fread(data.data() + old_size, 1, chunk, f);
    data.resize(old_size + got);
    if (got < chunk) break;
  }
  const int error = std::ferror(f) ? errno : 0;
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) throw IOError(path + ": cannot read file (" + errno_text(error) + ")");
  return data;
}

/// The lower-case extension of `path` (".off"), empty if it has none.
std::string extension_of(const std::string& path) { return lower(fs::path(path).extension().string()); }

[[noreturn]] void unknown_format(const std::string& path, const std::string& ext) {
  if (ext.empty())
    invalid(path, "unknown mesh format (no file extension; expected .off, .obj, .ply or .stl)");
  invalid(path, "unknown mesh format " + quote(ext) + " (expected .off, .obj, .ply or .stl)");
}

void check_empty(std::string_view data, const std::string& name) {
  if (data.empty()) invalid(name, "file is empty");
}

/// A capacity to reserve for `count` items that each take at least `min_bytes` of `bytes`.
std::size_t capped(unsigned long long count, std::size_t bytes, std::size_t min_bytes) {
  const unsigned long long cap = bytes / std::max<std::size_t>(min_bytes, 1) + 1;
  return static_cast<std::size_t>(std::min(count, cap));
}

// ------------------------------------------------------------------ OFF

/// "OFF", "COFF", "NOFF", "STCNOFF", ... (letters before OFF from "STCN4n").
bool is_off_keyword(std::string_view t) {
  if (t.size() < 3 || !iequals(t.substr(t.size() - 3), "OFF")) return false;
  for (char c : t.substr(0, t.size() - 3))
    if (std::strchr("STCN4n", c) == nullptr) return false;
  return true;
}

TriangleSoup parse_off(std::string_view text, const std::string& name) {
  text = skip_bom(text);
  check_empty(text, name);
  reject_binary(text, name, "OFF");
  Lines lines(text);
  std::string_view line;
  std::vector<std::string_view> tok;
  if (!lines.next_nonblank(line)) invalid(name, "file has no content (only blank lines and comments)");
  split(line, tok);
  std::size_t first = 0;
  if (is_off_keyword(tok[0])) {
    const std::string_view prefix = tok[0].substr(0, tok[0].size() - 3);
    if (prefix.find('4') != std::string_view::npos || prefix.find('n') != std::string_view::npos)
      invalid(name, "OFF files with 4 or n dimensions (" + quote(tok[0]) + ") are not supported");
    if (tok.size() > 1 && iequals(tok[1], "BINARY")) invalid(name, "binary OFF files are not supported");
    first = 1;
    if (tok.size() == 1) {
      if (!lines.next_nonblank(line))
        invalid(name, "unexpected end of file (missing the vertex and face counts)");
      split(line, tok);
      first = 0;
    }
  } else {
    long long dummy = 0;
    if (!parse_integer(tok[0], dummy))
      invalid(name, "not an OFF file (expected an 'OFF' header, found " + quote(tok[0]) + ")");
  }
  if (tok.size() < first + 2)
    invalid(name, line_prefix(lines.number()) + "expected the vertex and face counts");
  unsigned long long nv = 0, nf = 0;
  if (!parse_unsigned(tok[first], nv))
    invalid(name, line_prefix(lines.number()) + "vertex count " + quote(tok[first]) + " is not a valid count");
  if (!parse_unsigned(tok[first + 1], nf))
    invalid(name, line_prefix(lines.number()) + "face count " + quote(tok[first + 1]) + " is not a valid count");

  TriangleSoup soup;
  // A vertex line takes at least 6 bytes ("0 0 0\n"), a face line at least 8 ("3 0 1 2\n").
  soup.points.reserve(capped(nv, text.size(), 6));
  soup.triangles.reserve(capped(nf, text.size(), 8));
  for (unsigned long long i = 0; i < nv; ++i) {
    if (!lines.next_nonblank(line))
      invalid(name, "unexpected end of file after " + std::to_string(i) + " of " + std::to_string(nv) + " vertices");
    split(line, tok);
    if (tok.size() < 3)
      invalid(name, line_prefix(lines.number()) + "vertex " + std::to_string(i) + " has " +
                        std::to_string(tok.size()) + " coordinates, expected 3");
    Point3d p{};
    for (int c = 0; c < 3; ++c)
      if (!parse_double(tok[c], p[c]))
        invalid(name, line_prefix(lines.number()) + "vertex " + std::to_string(i) + ": " + quote(tok[c]) +
                          " is not a number");
    if (!finite3(p)) invalid(name, "vertex " + std::to_string(i) + " has a non-finite coordinate");
    soup.points.push_back(p);
  }
  for (unsigned long long f = 0; f < nf; ++f) {
    if (!lines.next_nonblank(line))
      invalid(name, "unexpected end of file after " + std::to_string(f) + " of " + std::to_string(nf) + " faces");
    split(line, tok);
    long long k = 0;
    if (!parse_integer(tok[0], k))
      invalid(name, line_prefix(lines.number()) + "face " + std::to_string(f) +
                        ": expected its number of vertices, found " + quote(tok[0]));
    if (k != 3)
      invalid(name, "face " + std::to_string(f) + " has " + std::to_string(k) +
                        " vertices; only triangles are supported");
    if (tok.size() < 4)
      invalid(name, line_prefix(lines.number()) + "face " + std::to_string(f) + " lists " +
                        std::to_string(tok.size() - 1) + " of its 3 vertex indices");
    std::array<std::size_t, 3> t{};
    for (int c = 0; c < 3; ++c) {
      long long index = 0;
      if (!parse_integer(tok[1 + c], index))
        invalid(name, line_prefix(lines.number()) + "face " + std::to_string(f) + ": " + quote(tok[1 + c]) +
                          " is not a vertex index");
      if (index < 0 || static_cast<unsigned long long>(index) >= nv)
        invalid(name, "face " + std::to_string(f) + " has a vertex index " + std::to_string(index) +
                          " out of range (mesh has " + std::to_string(nv) + " vertices)");
      t[c] = static_cast<std::size_t>(index);
    }
    soup.triangles.push_back(t);
  }
  // More content than the header declares: the counts are wrong, and reading the declared
  // number of faces only would silently drop the rest (an open mesh where a closed one was meant).
  if (lines.next_nonblank(line))
    invalid(name, line_prefix(lines.number()) + "data after the " + std::to_string(nf) +
                      " faces the header declares: " + quote_trimmed(line) + " (is the face count wrong?)");
  return soup;
}

// ------------------------------------------------------------------ OBJ

TriangleSoup parse_obj(std::string_view text, const std::string& name) {
  text = skip_bom(text);
  check_empty(text, name);
  reject_binary(text, name, "OBJ");
  Lines lines(text);
  std::string_view line;
  std::vector<std::string_view> tok;
  TriangleSoup soup;
  std::vector<std::size_t> face_line;  // line of each face, for range errors found at the end
  while (lines.next(line)) {
    split(line, tok);
    if (tok.empty()) continue;
    const std::size_t ln = lines.number();
    if (tok[0] == "v") {
      const std::size_t i = soup.points.size();
      if (tok.size() < 4)
        invalid(name, line_prefix(ln) + "vertex " + std::to_string(i) + " has " + std::to_string(tok.size() - 1) +
                          " coordinates, expected 3");
      Point3d p{};
      for (int c = 0; c < 3; ++c)
        if (!parse_double(tok[1 + c], p[c]))
          invalid(name, line_prefix(ln) + "vertex " + std::to_string(i) + ": " + quote(tok[1 + c]) +
                            " is not a number");
      if (!finite3(p)) invalid(name, line_prefix(ln) + "vertex " + std::to_string(i) + " has a non-finite coordinate");
      soup.points.push_back(p);
    } else if (tok[0] == "f") {
      const std::size_t f = soup.triangles.size();
      if (tok.size() != 4)
        invalid(name, line_prefix(ln) + "face " + std::to_string(f) + " has " + std::to_string(tok.size() - 1) +
                          " vertices; only triangles are supported");
      std::array<std::size_t, 3> t{};
      for (int c = 0; c < 3; ++c) {
        std::string_view entry = tok[1 + c];
        const std::string_view v = entry.substr(0, entry.find('/'));
        long long index = 0;
        if (!parse_integer(v, index))
          invalid(name, line_prefix(ln) + "face " + std::to_string(f) + ": " + quote(entry) +
                            " is not a vertex index");
        if (index == 0)
          invalid(name, line_prefix(ln) + "face " + std::to_string(f) +
                            " has a vertex index 0 (OBJ indices start at 1)");
        if (index < 0) {  // relative to the vertices defined so far
          const long long resolved = static_cast<long long>(soup.points.size()) + index;
          if (resolved < 0)
            invalid(name, line_prefix(ln) + "face " + std::to_string(f) + " has a vertex index " +
                              std::to_string(index) + " out of range (only " + std::to_string(soup.points.size()) +
                              " vertices are defined before it)");
          t[c] = static_cast<std::size_t>(resolved);
        } else {
          t[c] = static_cast<std::size_t>(index - 1);  // checked once all vertices are read
        }
      }
      soup.triangles.push_back(t);
      face_line.push_back(ln);
    } else if (const auto c = static_cast<unsigned char>(tok[0][0]); c < 0x21 || c > 0x7e) {
      // No OBJ statement starts with a byte outside printable ASCII: another encoding, or a
      // corrupted file (the line would otherwise be ignored, and a vertex with it).
      invalid(name, line_prefix(ln) + "unknown statement " + quote(tok[0]) + " (not an OBJ keyword)");
    }
    // vn, vt, vp, l, p, g, o, s, usemtl, mtllib, ...: ignored
  }
  if (soup.triangles.empty()) {
    if (soup.points.empty()) invalid(name, "no vertices or faces found (not an OBJ file?)");
    invalid(name, "file has no faces");
  }
  const std::size_t nv = soup.points.size();
  for (std::size_t f = 0; f < soup.triangles.size(); ++f)
    for (std::size_t index : soup.triangles[f])
      if (index >= nv)
        invalid(name, line_prefix(face_line[f]) + "face " + std::to_string(f) + " has a vertex index " +
                          std::to_string(index + 1) + " out of range (mesh has " + std::to_string(nv) +
                          " vertices)");
  return soup;
}

// ------------------------------------------------------------------ STL

/// Merges points with equal coordinates (-0.0 and 0.0 are equal).
class PointMerger {
 public:
  explicit PointMerger(TriangleSoup& soup) : soup_(soup) {}

  std::size_t add(Point3d p) {
    for (double& x : p) x += 0.0;  // -0.0 -> +0.0
    const auto [it, inserted] = index_.try_emplace(p, soup_.points.size());
    if (inserted) soup_.points.push_back(p);
    return it->second;
  }

 private:
  struct Hash {
    std::size_t operator()(const Point3d& p) const {
      std::uint64_t h = 0x9e3779b97f4a7c15ull;
      for (double x : p) {
        std::uint64_t bits = 0;
        std::memcpy(&bits, &x, sizeof bits);
        h ^= bits + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
      }
      return static_cast<std::size_t>(h);
    }
  };
  TriangleSoup& soup_;
  std::unordered_map<Point3d, std::size_t, Hash> index_;
};

std::uint32_t read_u32_le(const unsigned char* p) {
  return std::uint32_t(p[0]) | (std::uint32_t(p[1]) << 8) | (std::uint32_t(p[2]) << 16) | (std::uint32_t(p[3]) << 24);
}

float read_f32_le(const unsigned char* p) {
  const std::uint32_t bits = read_u32_le(p);
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

TriangleSoup parse_binary_stl(std::string_view data, const std::string& name, std::size_t count) {
  TriangleSoup soup;
  soup.triangles.reserve(count);
  PointMerger merger(soup);
  const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
  for (std::size_t f = 0; f < count; ++f) {
    const unsigned char* rec = bytes + 84 + 50 * f + 12;  // skip the normal
    std::array<std::size_t, 3> t{};
    for (int c = 0; c < 3; ++c) {
      Point3d p{read_f32_le(rec + 12 * c), read_f32_le(rec + 12 * c + 4), read_f32_le(rec + 12 * c + 8)};
      if (!finite3(p)) invalid(name, "facet " + std::to_string(f) + " has a non-finite coordinate");
      t[c] = merger.add(p);
    }
    soup.triangles.push_back(t);
  }
  return soup;
}

/// Whitespace-separated tokens of a whole text, with line numbers.
class TokenStream {
 public:
  explicit TokenStream(std::string_view text) : text_(text) {}

  bool next(std::string_view& token) {
    skip_space();
    if (pos_ >= text_.size()) return false;
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_]) && text_[pos_] != '\n') ++pos_;
    token = text_.substr(start, pos_ - start);
    token_line_ = line_;
    return true;
  }

  void skip_rest_of_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }

  std::size_t line() const { return token_line_; }      ///< line of the last token read
  std::size_t current_line() const { return line_; }
  std::size_t offset() const { return pos_; }

 private:
  void skip_space() {
    while (pos_ < text_.size() && (is_space(text_[pos_]) || text_[pos_] == '\n')) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
  std::size_t token_line_ = 1;
};

TriangleSoup parse_ascii_stl(std::string_view text, const std::string& name) {
  TokenStream ts(text);
  std::string_view tok;
  TriangleSoup soup;
  PointMerger merger(soup);
  std::size_t facet = 0;

  // Reads the next token and checks it is `keyword` (case-insensitive).
  const auto expect = [&](const char* keyword) {
    if (!ts.next(tok))
      invalid(name, "unexpected end of file in facet " + std::to_string(facet) + " (expected '" + keyword + "')");
    if (!iequals(tok, keyword))
      invalid(name, line_prefix(ts.line()) + "expected '" + keyword + "', found " + quote(tok));
  };

  if (!ts.next(tok) || !iequals(tok, "solid")) invalid(name, "not an ASCII STL file (no 'solid' header)");
  ts.skip_rest_of_line();  // the solid's name
  for (;;) {
    if (!ts.next(tok)) invalid(name, "unexpected end of file after " + std::to_string(facet) + " facets (expected 'endsolid')");
    if (iequals(tok, "endsolid")) {
      ts.skip_rest_of_line();
      // Another solid may follow; anything else after 'endsolid' is refused (truncated or
      // concatenated files would otherwise lose their rest silently).
      if (!ts.next(tok)) break;
      if (iequals(tok, "solid")) {
        ts.skip_rest_of_line();
        continue;
      }
      invalid(name, line_prefix(ts.line()) + "data after 'endsolid': " + quote(tok) +
                        " (expected the end of the file or another 'solid')");
    }
    if (!iequals(tok, "facet"))
      invalid(name, line_prefix(ts.line()) + "expected 'facet' or 'endsolid', found " + quote(tok));
    expect("normal");
    for (int c = 0; c < 3; ++c)  // the normal is recomputed from the vertices, its values are not used
      if (!ts.next(tok)) invalid(name, "unexpected end of file in facet " + std::to_string(facet));
    expect("outer");
    expect("loop");
    std::array<std::size_t, 3> t{};
    std::size_t k = 0;
    for (;;) {
      if (!ts.next(tok)) invalid(name, "unexpected end of file in facet " + std::to_string(facet));
      if (iequals(tok, "endloop")) break;
      if (!iequals(tok, "vertex"))
        invalid(name, line_prefix(ts.line()) + "expected 'vertex' or 'endloop', found " + quote(tok));
      Point3d p{};
      for (int c = 0; c < 3; ++c) {
        if (!ts.next(tok)) invalid(name, "unexpected end of file in facet " + std::to_string(facet));
        if (!parse_double(tok, p[c]))
          invalid(name, line_prefix(ts.line()) + "facet " + std::to_string(facet) + ": " + quote(tok) +
                            " is not a number");
      }
      if (!finite3(p)) invalid(name, "facet " + std::to_string(facet) + " has a non-finite coordinate");
      if (k < 3) t[k] = merger.add(p);
      ++k;
    }
    if (k != 3)
      invalid(name, "facet " + std::to_string(facet) + " has " + std::to_string(k) +
                        " vertices; only triangles are supported");
    expect("endfacet");
    soup.triangles.push_back(t);
    ++facet;
  }
  return soup;
}

TriangleSoup parse_stl(std::string_view data, const std::string& name) {
  check_empty(data, name);
  if (data.size() >= 84) {
    const std::uint32_t count = read_u32_le(reinterpret_cast<const unsigned char*>(data.data()) + 80);
    if (static_cast<std::uint64_t>(data.size()) == 84 + 50 * static_cast<std::uint64_t>(count))
      return parse_binary_stl(data, name, count);
  }
  data = skip_bom(data);  // ASCII from here on
  check_empty(data, name);
  std::size_t i = 0;
  while (i < data.size() && (is_space(data[i]) || data[i] == '\n')) ++i;
  if (!iequals(data.substr(i, std::min<std::size_t>(5, data.size() - i)), "solid")) {
    if (data.size() < 84)
      invalid(name, "not an STL file (no 'solid' header, and " + std::to_string(data.size()) +
                        " bytes is too short for a binary STL)");
    const std::uint32_t count = read_u32_le(reinterpret_cast<const unsigned char*>(data.data()) + 80);
    invalid(name, "not an STL file (no 'solid' header, and its size of " + std::to_string(data.size()) +
                      " bytes does not match the " +
                      std::to_string(84 + 50 * static_cast<std::uint64_t>(count)) +
                      " bytes of a binary STL with " + std::to_string(count) + " triangles)");
  }
  return parse_ascii_stl(data, name);
}

// ------------------------------------------------------------------ PLY

enum class PlyType { i8, u8, i16, u16, i32, u32, f32, f64 };

bool ply_type(std::string_view s, PlyType& t) {
  static const std::pair<const char*, PlyType> names[] = {
      {"char", PlyType::i8},    {"int8", PlyType::i8},     {"uchar", PlyType::u8},   {"uint8", PlyType::u8},
      {"short", PlyType::i16},  {"int16", PlyType::i16},   {"ushort", PlyType::u16}, {"uint16", PlyType::u16},
      {"int", PlyType::i32},    {"int32", PlyType::i32},   {"uint", PlyType::u32},   {"uint32", PlyType::u32},
      {"float", PlyType::f32},  {"float32", PlyType::f32}, {"double", PlyType::f64}, {"float64", PlyType::f64}};
  for (const auto& [n, type] : names)
    if (s == n) {
      t = type;
      return true;
    }
  return false;
}

std::size_t ply_size(PlyType t) {
  switch (t) {
    case PlyType::i8: case PlyType::u8: return 1;
    case PlyType::i16: case PlyType::u16: return 2;
    case PlyType::i32: case PlyType::u32: case PlyType::f32: return 4;
    case PlyType::f64: return 8;
  }
  return 1;
}

struct PlyProperty {
  std::string name;
  bool is_list = false;
  PlyType count_type = PlyType::u8;
  PlyType type = PlyType::f32;
};

struct PlyElement {
  std::string name;
  unsigned long long count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyFormat { ascii, binary_le, binary_be };

/// Reads the values of a PLY body, ASCII or binary.
class PlyBody {
 public:
  enum Status { ok, eof, bad };

  PlyBody(std::string_view data, PlyFormat format, std::size_t first_line)
      : data_(data), format_(format), tokens_(data), first_line_(first_line) {}

  Status read(PlyType t, double& v) {
    if (format_ == PlyFormat::ascii) {
      if (!tokens_.next(token_)) return eof;
      return parse_double(token_, v) ? ok : bad;
    }
    const std::size_t n = ply_size(t);
    if (data_.size() - pos_ < n) return eof;
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, n);
    pos_ += n;
    if (format_ == PlyFormat::binary_be) std::reverse(b, b + n);  // to little endian
    std::uint64_t u = 0;
    for (std::size_t i = 0; i < n; ++i) u |= std::uint64_t(b[i]) << (8 * i);
    switch (t) {
      case PlyType::i8: v = static_cast<std::int8_t>(u); break;
      case PlyType::u8: v = static_cast<std::uint8_t>(u); break;
      case PlyType::i16: v = static_cast<std::int16_t>(u); break;
      case PlyType::u16: v = static_cast<std::uint16_t>(u); break;
      case PlyType::i32: v = static_cast<std::int32_t>(u); break;
      case PlyType::u32: v = static_cast<std::uint32_t>(u); break;
      case PlyType::f32: {
        const auto bits = static_cast<std::uint32_t>(u);
        float f;
        std::memcpy(&f, &bits, sizeof f);
        v = f;
        break;
      }
      case PlyType::f64: std::memcpy(&v, &u, sizeof v); break;
    }
    return ok;
  }

  /// Skips `n` values of type t; false at the end of the data (or on a bad ASCII value).
  Status skip(PlyType t, unsigned long long n) {
    if (format_ != PlyFormat::ascii) {
      const unsigned long long bytes = n * ply_size(t);
      if (n > data_.size() || data_.size() - pos_ < bytes) return eof;
      pos_ += static_cast<std::size_t>(bytes);
      return ok;
    }
    double v = 0;
    for (unsigned long long i = 0; i < n; ++i) {
      const Status s = read(t, v);
      if (s != ok) return s;
    }
    return ok;
  }

  /// What follows the last element, for a message: "line N: data 'x'" (ASCII; blanks are not
  /// data) or "N bytes of data" (binary); empty if nothing does.
  std::string trailing() {
    if (format_ == PlyFormat::ascii) {
      if (!tokens_.next(token_)) return std::string();
      return where() + "data " + quote(token_);
    }
    if (pos_ == data_.size()) return std::string();
    const std::size_t n = data_.size() - pos_;
    return std::to_string(n) + (n == 1 ? " byte" : " bytes") + " of data";
  }

  std::size_t remaining() const {
    return format_ == PlyFormat::ascii ? data_.size() - tokens_.offset() : data_.size() - pos_;
  }
  bool ascii() const { return format_ == PlyFormat::ascii; }
  /// "line N: " for ASCII bodies, "" for binary ones.
  std::string where() const {
    return ascii() ? line_prefix(first_line_ + tokens_.line() - 1) : std::string();
  }
  std::string_view token() const { return token_; }

 private:
  std::string_view data_;
  PlyFormat format_;
  std::size_t pos_ = 0;
  TokenStream tokens_;
  std::string_view token_;
  std::size_t first_line_;
};

/// A PLY header: the format and the elements with their properties.
struct PlyHeader {
  PlyFormat format = PlyFormat::ascii;
  std::vector<PlyElement> elements;
};

PlyHeader parse_ply_header(Lines& lines, const std::string& name) {
  std::string_view line;
  std::vector<std::string_view> tok;
  if (!lines.next(line) || (line != "ply" && line != "ply\r")) invalid(name, "not a PLY file (missing 'ply' header)");
  bool have_format = false;
  PlyHeader header;
  auto& elements = header.elements;
  for (;;) {
    if (!lines.next(line)) invalid(name, "unexpected end of file in the PLY header (missing 'end_header')");
    split(line, tok);
    const std::string where = line_prefix(lines.number());
    if (tok.empty()) continue;
    if (tok[0] == "end_header") break;
    if (tok[0] == "comment" || tok[0] == "obj_info") continue;
    if (tok[0] == "format") {
      if (tok.size() < 2) invalid(name, where + "'format' needs a value");
      if (tok[1] == "ascii") header.format = PlyFormat::ascii;
      else if (tok[1] == "binary_little_endian") header.format = PlyFormat::binary_le;
      else if (tok[1] == "binary_big_endian") header.format = PlyFormat::binary_be;
      else invalid(name, where + "unknown PLY format " + quote(tok[1]));
      have_format = true;
    } else if (tok[0] == "element") {
      if (tok.size() != 3) invalid(name, where + "expected 'element <name> <count>'");
      PlyElement e;
      e.name = std::string(tok[1]);
      if (!parse_unsigned(tok[2], e.count))
        invalid(name, where + "element " + quote(tok[1]) + " has an invalid count " + quote(tok[2]));
      for (const PlyElement& other : elements)
        if (other.name == e.name) invalid(name, where + "element " + quote(tok[1]) + " is declared twice");
      elements.push_back(std::move(e));
    } else if (tok[0] == "property") {
      if (elements.empty()) invalid(name, where + "'property' before any 'element'");
      PlyProperty p;
      if (tok.size() == 5 && tok[1] == "list") {
        p.is_list = true;
        if (!ply_type(tok[2], p.count_type)) invalid(name, where + "unknown property type " + quote(tok[2]));
        if (!ply_type(tok[3], p.type)) invalid(name, where + "unknown property type " + quote(tok[3]));
        p.name = std::string(tok[4]);
      } else if (tok.size() == 3) {
        if (!ply_type(tok[1], p.type)) invalid(name, where + "unknown property type " + quote(tok[1]));
        p.name = std::string(tok[2]);
      } else {
        invalid(name, where + "expected 'property <type> <name>' or 'property list <type> <type> <name>'");
      }
      elements.back().properties.push_back(std::move(p));
    } else {
      invalid(name, where + "unexpected " + quote(tok[0]) + " in the PLY header");
    }
  }
  if (!have_format) invalid(name, "the PLY header has no 'format' line");
  return header;
}

/// Where the mesh is in a PLY file: its vertex and face elements, the positions of x, y, z among
/// the vertex properties and of the index list among the face properties.
struct PlyLayout {
  const PlyElement* vertex = nullptr;
  const PlyElement* face = nullptr;
  int xyz[3] = {-1, -1, -1};
  int indices = -1;
};

PlyLayout ply_layout(const PlyHeader& header, const std::string& name) {
  PlyLayout layout;
  for (const PlyElement& e : header.elements) {
    if (e.name == "vertex") layout.vertex = &e;
    if (e.name == "face") layout.face = &e;
  }
  if (layout.vertex == nullptr) invalid(name, "the PLY header declares no 'vertex' element");
  if (layout.face == nullptr) invalid(name, "the PLY header declares no 'face' element (point clouds are not supported)");
  for (std::size_t i = 0; i < layout.vertex->properties.size(); ++i) {
    const PlyProperty& p = layout.vertex->properties[i];
    for (int c = 0; c < 3; ++c)
      if (!p.is_list && p.name == std::string(1, char('x' + c))) layout.xyz[c] = static_cast<int>(i);
  }
  for (int c = 0; c < 3; ++c)
    if (layout.xyz[c] < 0) invalid(name, "the PLY vertex element has no '" + std::string(1, char('x' + c)) + "' property");
  for (std::size_t i = 0; i < layout.face->properties.size(); ++i) {
    const PlyProperty& p = layout.face->properties[i];
    if (p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) layout.indices = static_cast<int>(i);
  }
  if (layout.indices < 0) invalid(name, "the PLY face element has no 'vertex_indices' list property");
  return layout;
}

/// Reads element `e`'s entries from the body: vertices and faces into `soup`, others skipped.
void read_ply_element(PlyBody& body, const PlyElement& e, const PlyLayout& layout, TriangleSoup& soup,
                      const std::string& name) {
  const bool is_vertex = &e == layout.vertex;
  const bool is_face = &e == layout.face;
  const std::string plural = is_vertex ? "vertices" : is_face ? "faces" : "entries of element " + quote(e.name);
  std::size_t min_bytes = 0;
  for (const PlyProperty& p : e.properties) min_bytes += body.ascii() ? 2 : ply_size(p.is_list ? p.count_type : p.type);
  if (is_vertex) soup.points.reserve(capped(e.count, body.remaining(), min_bytes));
  if (is_face) soup.triangles.reserve(capped(e.count, body.remaining(), min_bytes));
  // An element without properties takes no bytes: do not count to its declared 10^13 entries
  // (a timeout found by fuzzing). Vertex and face elements have their properties checked above.
  if (e.properties.empty() && !is_vertex && !is_face) return;
  for (unsigned long long i = 0; i < e.count; ++i) {
    const auto fail = [&](PlyBody::Status s) {
      if (s == PlyBody::eof)
        invalid(name, "unexpected end of file after " + std::to_string(i) + " of " + std::to_string(e.count) + " " + plural);
      invalid(name, body.where() + quote(body.token()) + " is not a number");
    };
    Point3d point{};
    std::array<std::size_t, 3> triangle{};
    for (std::size_t k = 0; k < e.properties.size(); ++k) {
      const PlyProperty& p = e.properties[k];
      double v = 0;
      if (!p.is_list) {
        if (const auto s = body.read(p.type, v); s != PlyBody::ok) fail(s);
        if (is_vertex)
          for (int c = 0; c < 3; ++c)
            if (layout.xyz[c] == static_cast<int>(k)) point[c] = v;
        continue;
      }
      if (const auto s = body.read(p.count_type, v); s != PlyBody::ok) fail(s);
      if (!(v >= 0 && v <= 4294967295.0 && v == std::floor(v)))
        invalid(name, body.where() + std::string(is_face ? "face " : "entry ") + std::to_string(i) +
                          " has an invalid list length " + quote(body.ascii() ? body.token() : std::to_string(v)));
      const auto n = static_cast<unsigned long long>(v);
      if (!is_face || static_cast<int>(k) != layout.indices) {
        if (const auto s = body.skip(p.type, n); s != PlyBody::ok) fail(s);
        continue;
      }
      if (n != 3)
        invalid(name, "face " + std::to_string(i) + " has " + std::to_string(n) + " vertices; only triangles are supported");
      for (int c = 0; c < 3; ++c) {
        if (const auto s = body.read(p.type, v); s != PlyBody::ok) fail(s);
        if (v != std::floor(v) || !std::isfinite(v))
          invalid(name, body.where() + "face " + std::to_string(i) + " has a vertex index that is not an integer");
        if (v < 0 || v >= 18446744073709551615.0)
          invalid(name, "face " + std::to_string(i) + " has a vertex index " + integral_text(v) +
                            " out of range (mesh has " + std::to_string(layout.vertex->count) + " vertices)");
        triangle[c] = static_cast<std::size_t>(v);
      }
    }
    if (is_vertex) {
      if (!finite3(point)) invalid(name, "vertex " + std::to_string(i) + " has a non-finite coordinate");
      soup.points.push_back(point);
    }
    if (is_face) soup.triangles.push_back(triangle);
  }
}

TriangleSoup parse_ply(std::string_view data, const std::string& name) {
  data = skip_bom(data);
  check_empty(data, name);
  Lines lines(data, /*strip_comments=*/false);
  const PlyHeader header = parse_ply_header(lines, name);
  const PlyLayout layout = ply_layout(header, name);
  PlyBody body(data.substr(lines.offset()), header.format, lines.number() + 1);
  TriangleSoup soup;
  for (const PlyElement& e : header.elements) read_ply_element(body, e, layout, soup, name);
  // More content than the header declares (the counts are wrong): refused, as in OFF files.
  if (const std::string extra = body.trailing(); !extra.empty())
    invalid(name, extra + " after the " + std::to_string(layout.vertex->count) + " vertices and " +
                      std::to_string(layout.face->count) + " faces the header declares (is a count wrong?)");
  const std::size_t nv = soup.points.size();
  for (std::size_t f = 0; f < soup.triangles.size(); ++f)
    for (std::size_t index : soup.triangles[f])
      if (index >= nv)
        invalid(name, "face " + std::to_string(f) + " has a vertex index " + std::to_string(index) +
                          " out of range (mesh has " + std::to_string(nv) + " vertices)");
  return soup;
}

// ------------------------------------------------------------------ validation helpers

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) {
    for (std::size_t i = 0; i < n; ++i) parent_[i] = i;
  }
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::size_t> parent_;
};

std::string edge_text(std::size_t a, std::size_t b) {
  return "(" + std::to_string(a) + ", " + std::to_string(b) + ")";
}

// ------------------------------------------------------------------ writing

void check_indices(const TriangleSoup& soup, const std::string& name) {
  const std::size_t nv = soup.points.size();
  for (std::size_t f = 0; f < soup.triangles.size(); ++f)
    for (std::size_t index : soup.triangles[f])
      if (index >= nv)
        invalid(name, "face " + std::to_string(f) + " has a vertex index " + std::to_string(index) +
                          " out of range (mesh has " + std::to_string(nv) + " vertices)");
}

void write_point(std::ostream& out, const Point3d& p) { out << p[0] << ' ' << p[1] << ' ' << p[2]; }

void write_off(std::ostream& out, const TriangleSoup& soup) {
  out << "OFF\n" << soup.points.size() << ' ' << soup.triangles.size() << " 0\n";
  for (const Point3d& p : soup.points) {
    write_point(out, p);
    out << '\n';
  }
  for (const auto& t : soup.triangles) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
}

void write_obj(std::ostream& out, const TriangleSoup& soup) {
  out << "# written by seam\n";
  for (const Point3d& p : soup.points) {
    out << "v ";
    write_point(out, p);
    out << '\n';
  }
  for (const auto& t : soup.triangles) out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
}

void write_ply(std::ostream& out, const TriangleSoup& soup) {
  out << "ply\nformat ascii 1.0\ncomment written by seam\n"
      << "element vertex " << soup.points.size() << '\n'
      << "property double x\nproperty double y\nproperty double z\n"
      << "element face " << soup.triangles.size() << '\n'
      << "property list uchar int vertex_indices\nend_header\n";
  for (const Point3d& p : soup.points) {
    write_point(out, p);
    out << '\n';
  }
  for (const auto& t : soup.triangles) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
}

void write_stl(std::ostream& out, const TriangleSoup& soup) {
  out << "solid seam\n";
  for (const auto& t : soup.triangles) {
    const Point3d& a = soup.points[t[0]];
    const Point3d& b = soup.points[t[1]];
    const Point3d& c = soup.points[t[2]];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    Point3d n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (len > 0 && std::isfinite(len))
      for (double& x : n) x /= len;
    else
      n = {0.0, 0.0, 0.0};
    out << "  facet normal ";
    write_point(out, n);
    out << "\n    outer loop\n";
    for (const Point3d* p : {&a, &b, &c}) {
      out << "      vertex ";
      write_point(out, *p);
      out << '\n';
    }
    out << "    endloop\n  endfacet\n";
  }
  out << "endsolid seam\n";
}

}  // namespace

// ================================================================== public functions

TriangleSoup read_triangle_mesh(const std::string& path) {
  const std::string ext = extension_of(path);
  if (ext != ".off" && ext != ".obj" && ext != ".ply" && ext != ".stl") unknown_format(path, ext);
  return parse_triangle_mesh(read_file(path), ext, path);
}

TriangleSoup parse_triangle_mesh(std::string_view data, const std::string& format, const std::string& name) {
  const std::string ext = lower(format.empty() || format[0] == '.' ? format : "." + format);
  TriangleSoup soup;
  if (ext == ".off") soup = parse_off(data, name);
  else if (ext == ".obj") soup = parse_obj(data, name);
  else if (ext == ".ply") soup = parse_ply(data, name);
  else if (ext == ".stl") soup = parse_stl(data, name);
  else unknown_format(name, ext);
  validate_triangle_mesh(soup, name);
  return soup;
}

namespace {

std::string coordinate_text(double x) {
  std::ostringstream os;
  os.imbue(std::locale::classic());
  os << std::setprecision(3) << x;
  return os.str();
}

/// Throws InvalidInput naming point i when a coordinate of p is beyond the supported magnitude.
void check_magnitude(const Point3d& p, std::size_t i, const std::string& name, bool whole_mesh) {
  using R = SupportedCoordinates;
  for (int c = 0; c < 3; ++c)
    if (!(std::abs(p[c]) <= R::max_magnitude))  // also NaN
      invalid(name, (whole_mesh ? "vertex " : "point ") + std::to_string(i) + " has a coordinate " +
                        coordinate_text(p[c]) + ", beyond the supported magnitude " +
                        coordinate_text(R::max_magnitude) + " (scale the input down)");
}

}  // namespace

void check_coordinate_range(const std::vector<Point3d>& points, const std::string& name, bool whole_mesh) {
  using R = SupportedCoordinates;
  const auto text = coordinate_text;
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, magnitude = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Point3d& p = points[i];
    check_magnitude(p, i, name, whole_mesh);
    for (int c = 0; c < 3; ++c) {
      lo[c] = i == 0 ? p[c] : std::min(lo[c], p[c]);
      hi[c] = i == 0 ? p[c] : std::max(hi[c], p[c]);
      magnitude = std::max(magnitude, std::abs(p[c]));
    }
  }
  if (!whole_mesh || points.empty()) return;
  // Rounded, as a size: the thresholds are many orders of magnitude from any rounding here.
  const double extent = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                  (hi[2] - lo[2]) * (hi[2] - lo[2]));
  if (extent < R::min_extent)
    invalid(name, "the mesh is " + text(extent) + " across, below the supported size " + text(R::min_extent) +
                      " (scale the input up)");
  if (extent < R::min_extent_to_position * magnitude)
    invalid(name, "the mesh is " + text(extent) + " across but lies " + text(magnitude) +
                      " from the origin: doubles cannot resolve it there (size below " +
                      text(R::min_extent_to_position) + " of the position; translate it nearer the origin)");
}

void validate_triangle_mesh(const TriangleSoup& soup, const std::string& name) {
  const std::size_t nv = soup.points.size();
  const std::size_t nf = soup.triangles.size();
  if (nf == 0) invalid(name, "mesh has no triangles");
  for (std::size_t i = 0; i < nv; ++i)
    if (!finite3(soup.points[i])) invalid(name, "vertex " + std::to_string(i) + " has a non-finite coordinate");
  check_coordinate_range(soup.points, name);

  // Per face: indices in range, no repeated vertex, non-zero area (exact test).
  for (std::size_t f = 0; f < nf; ++f) {
    const auto& t = soup.triangles[f];
    for (std::size_t index : t)
      if (index >= nv)
        invalid(name, "face " + std::to_string(f) + " has a vertex index " + std::to_string(index) +
                          " out of range (mesh has " + std::to_string(nv) + " vertices)");
    for (int a = 0; a < 3; ++a)
      for (int b = a + 1; b < 3; ++b)
        if (t[a] == t[b]) invalid(name, "face " + std::to_string(f) + " repeats vertex " + std::to_string(t[a]));
    using P = Filtered::Point_3;
    const auto point = [&](std::size_t i) { return P(soup.points[i][0], soup.points[i][1], soup.points[i][2]); };
    if (CGAL::collinear(point(t[0]), point(t[1]), point(t[2])))
      invalid(name, "face " + std::to_string(f) + " has zero area (its vertices are collinear)");
  }

  // Edges: at most two faces each, in opposite directions.
  struct HalfEdge {
    std::size_t lo, hi, face;
    bool forward;  // the face goes lo -> hi
  };
  std::vector<HalfEdge> edges;
  edges.reserve(3 * nf);
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const std::size_t u = soup.triangles[f][k], v = soup.triangles[f][(k + 1) % 3];
      edges.push_back({std::min(u, v), std::max(u, v), f, u < v});
    }
  std::sort(edges.begin(), edges.end(), [](const HalfEdge& a, const HalfEdge& b) {
    return std::tie(a.lo, a.hi, a.face) < std::tie(b.lo, b.hi, b.face);
  });
  // Corners (3 f + k) around the same vertex, joined through the edges shared by two faces.
  UnionFind fans(3 * nf);
  const auto corner = [&](std::size_t f, std::size_t v) {
    const auto& t = soup.triangles[f];
    return 3 * f + (t[0] == v ? 0 : t[1] == v ? 1 : 2);
  };
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
    const HalfEdge& a = edges[i];
    if (j - i > 2)
      invalid(name, "edge " + edge_text(a.lo, a.hi) + " is shared by " + std::to_string(j - i) +
                        " faces (non-manifold)");
    if (j - i == 2) {
      const HalfEdge& b = edges[i + 1];
      if (a.forward == b.forward)
        invalid(name, "faces " + std::to_string(a.face) + " and " + std::to_string(b.face) + " use edge " +
                          (a.forward ? edge_text(a.lo, a.hi) : edge_text(a.hi, a.lo)) +
                          " in the same direction (inconsistent orientation)");
      fans.unite(corner(a.face, a.lo), corner(b.face, a.lo));
      fans.unite(corner(a.face, a.hi), corner(b.face, a.hi));
    }
    i = j;
  }
  // Every vertex's corners must form one fan.
  std::vector<std::pair<std::size_t, std::size_t>> vertex_fan;  // (vertex, fan root)
  vertex_fan.reserve(3 * nf);
  for (std::size_t f = 0; f < nf; ++f)
    for (std::size_t k = 0; k < 3; ++k) vertex_fan.emplace_back(soup.triangles[f][k], fans.find(3 * f + k));
  std::sort(vertex_fan.begin(), vertex_fan.end());
  vertex_fan.erase(std::unique(vertex_fan.begin(), vertex_fan.end()), vertex_fan.end());
  for (std::size_t i = 0; i < vertex_fan.size();) {
    std::size_t j = i + 1;
    while (j < vertex_fan.size() && vertex_fan[j].first == vertex_fan[i].first) ++j;
    if (j - i > 1)
      invalid(name, "vertex " + std::to_string(vertex_fan[i].first) + " is non-manifold (its faces form " +
                        std::to_string(j - i) + " separate fans)");
    i = j;
  }
}

std::vector<std::vector<Point3d>> read_polylines(const std::string& path) {
  return parse_polylines(read_file(path), path);
}

std::vector<std::vector<Point3d>> parse_polylines(std::string_view data, const std::string& path) {
  data = skip_bom(data);
  if (data.empty()) invalid(path, "file is empty (no polyline found)");
  reject_binary(data, path, "polyline");
  Lines lines(data);
  std::string_view line;
  std::vector<std::vector<Point3d>> result;
  // The tokens of a line are read one at a time, never stored: a line of 10 million points would
  // otherwise hold 30 million views (480 MB) beside the file and the points (issue 22, class 8).
  const auto next_token = [](std::string_view text, std::size_t& pos) {
    while (pos < text.size() && is_space(text[pos])) ++pos;
    const std::size_t start = pos;
    while (pos < text.size() && !is_space(text[pos])) ++pos;
    return text.substr(start, pos - start);
  };
  while (lines.next_nonblank(line)) {
    const std::string where = line_prefix(lines.number());
    std::size_t pos = 0;
    const std::string_view count = next_token(line, pos);
    unsigned long long n = 0;
    if (!parse_unsigned(count, n)) {
      double d = 0;
      if (parse_double(count, d))
        invalid(path, where + "the point count " + quote(count) + " is not a non-negative integer");
      invalid(path, where + quote(count) + " is not a number");
    }
    if (n < 1) invalid(path, where + "polyline needs at least 1 point (one point: an isolated point of contact)");
    const std::size_t first = pos;
    std::size_t found = 0;
    for (std::size_t p = first; !next_token(line, p).empty();) ++found;
    if (n > found || 3 * n != found) {
      const unsigned long long max = std::numeric_limits<unsigned long long>::max();
      invalid(path, where + "expected " + (n <= max / 3 ? std::to_string(3 * n) : std::to_string(n) + " x 3") +
                        " coordinates after the count " + std::to_string(n) + ", found " + std::to_string(found));
    }
    std::vector<Point3d> polyline(n);
    for (std::size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) {
        const std::string_view t = next_token(line, pos);
        if (!parse_double(t, polyline[i][c])) invalid(path, where + quote(t) + " is not a number");
        if (!std::isfinite(polyline[i][c])) invalid(path, where + "non-finite coordinate");
      }
    check_coordinate_range(polyline, path + ": " + where.substr(0, where.size() - 2), false);
    result.push_back(std::move(polyline));
  }
  if (result.empty()) invalid(path, "no polyline found");
  return result;
}

// ================================================================== output files

namespace {

/// Every temporary output file and made directory of the process not yet committed or
/// discarded, for remove_temporary_outputs(). Never destroyed (a signal-handling thread may use
/// it while the process exits).
struct TemporaryRegistry {
  std::mutex mutex;
  std::map<std::uint64_t, std::string> files;
  std::map<std::uint64_t, std::vector<std::string>> directories;  ///< per set, in creation order
  std::uint64_t next_id = 0;
  bool closed = false;  ///< after remove_temporary_outputs(): nothing may be created or renamed
};

TemporaryRegistry& registry() {
  static TemporaryRegistry* r = new TemporaryRegistry;
  return *r;
}

/// The permissions a new file gets (0666 less the umask), as the temporary file must have them
/// when it is renamed (mkstemp makes it 0600). Read once, under the registry's lock.
mode_t new_file_mode() {
  static const mode_t mode = [] {
    const mode_t mask = ::umask(0);
    ::umask(mask);
    return static_cast<mode_t>(0666 & ~mask);
  }();
  return mode;
}

[[noreturn]] void cannot_write(const std::string& path, const std::string& reason) {
  throw IOError(path + ": cannot write (" + reason + ")");
}

const char* file_kind(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

/// The final target of `path`: symbolic links followed (at most 40); `path` itself when it does
/// not exist. Throws IOError when a component cannot be examined (not a directory, too long,
/// permission denied) or the target exists and is not a regular file.
std::string output_target(const std::string& path) {
  std::string target = path;
  for (int hops = 0;; ++hops) {
    struct stat st {};
    if (::lstat(target.c_str(), &st) != 0) {
      if (errno == ENOENT) {
        // The file may be missing; its directory must exist (mkstemp says so otherwise).
        return target;
      }
      cannot_write(path, errno_text(errno));
    }
    if (S_ISREG(st.st_mode)) return target;
    if (!S_ISLNK(st.st_mode)) {
      if (S_ISDIR(st.st_mode)) cannot_write(path, "is a directory");
      cannot_write(path, std::string("is ") + file_kind(st.st_mode) + ", not a regular file; only regular files are replaced");
    }
    if (hops == 40) cannot_write(path, errno_text(ELOOP));
    std::error_code ec;
    const fs::path link = fs::read_symlink(target, ec);
    if (ec) cannot_write(path, ec.message());
    target = link.is_absolute() ? link.string() : (fs::path(target).parent_path() / link).string();
  }
}

/// A stream buffer writing to a file descriptor that keeps the first write error's errno.
class FdBuffer : public std::streambuf {
 public:
  explicit FdBuffer(int fd) : fd_(fd), buffer_(1 << 16) { setp(buffer_.data(), buffer_.data() + buffer_.size()); }
  int error() const { return error_; }

 protected:
  int_type overflow(int_type c) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  bool drain() {
    if (error_ != 0) return false;
    const char* p = pbase();
    while (p < pptr()) {
      const ssize_t n = ::write(fd_, p, static_cast<std::size_t>(pptr() - p));
      if (n < 0) {
        if (errno == EINTR) continue;
        error_ = errno;
        return false;
      }
      if (n == 0) {
        error_ = EIO;
        return false;
      }
      p += n;
    }
    setp(buffer_.data(), buffer_.data() + buffer_.size());
    return true;
  }
  int fd_;
  std::vector<char> buffer_;
  int error_ = 0;
};

}  // namespace

struct OutputFiles::Impl {
  struct Output {
    std::string path, target, temporary;
    fs::path canonical;  ///< of the target, to find two outputs with the same target
    std::uint64_t id = 0;
    int fd = -1;
    bool written = false, renamed = false, last = false;
  };
  std::vector<Output> outputs;
  std::uint64_t set_id = 0;
  bool has_directories = false;
};

OutputFiles::OutputFiles() : impl_(std::make_unique<Impl>()) {
  TemporaryRegistry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  impl_->set_id = r.next_id++;
}

OutputFiles::~OutputFiles() { discard(); }

std::size_t OutputFiles::size() const { return impl_->outputs.size(); }

void OutputFiles::create_directory(const std::string& dir) {
  if (dir.empty()) return;
  // The missing ancestors, outermost first.
  std::vector<fs::path> missing;
  std::error_code ec;
  for (fs::path p = fs::path(dir); !p.empty(); p = p.parent_path()) {
    const fs::file_status st = fs::status(p, ec);
    if (fs::exists(st)) {
      if (!fs::is_directory(st)) throw IOError(dir + ": cannot create the directory (" + p.string() + " is not a directory)");
      break;
    }
    missing.push_back(p);
    if (p == p.parent_path()) break;
  }
  TemporaryRegistry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  if (r.closed) throw IOError(dir + ": cannot create the directory (the process is being interrupted)");
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (::mkdir(it->c_str(), 0777) != 0 && errno != EEXIST)
      throw IOError(dir + ": cannot create the directory (" + errno_text(errno) + ")");
    r.directories[impl_->set_id].push_back(it->string());
    impl_->has_directories = true;
  }
}

std::size_t OutputFiles::add(const std::string& path, bool last) {
  if (path.empty()) throw InvalidInput("an output path is empty");
  Impl::Output out;
  out.path = path;
  out.last = last;
  out.target = output_target(path);
  std::error_code ec;
  out.canonical = fs::weakly_canonical(fs::absolute(out.target, ec), ec);
  if (ec) out.canonical.clear();
  for (const Impl::Output& other : impl_->outputs)
    if (!out.canonical.empty() && out.canonical == other.canonical)
      throw InvalidInput(path + ": the same path is given for two outputs (" + other.path + ")");
  const fs::path parent = fs::path(out.target).parent_path();
  std::string pattern = ((parent.empty() ? fs::path(".") : parent) / ".seam-XXXXXX").string();
  TemporaryRegistry& r = registry();
  {
    std::lock_guard<std::mutex> lock(r.mutex);
    if (r.closed) cannot_write(path, "the process is being interrupted");
    const int fd = ::mkstemp(pattern.data());
    if (fd < 0) cannot_write(path, errno_text(errno));
    out.fd = fd;
    out.temporary = pattern;
    out.id = r.next_id++;
    r.files[out.id] = pattern;
    ::fchmod(fd, new_file_mode());
  }
  impl_->outputs.push_back(std::move(out));
  return impl_->outputs.size() - 1;
}

void OutputFiles::write(std::size_t i, const std::function<void(std::ostream&)>& fill) {
  Impl::Output& out = impl_->outputs.at(i);
  if (out.written || out.fd < 0) throw std::logic_error("OutputFiles::write: output " + out.path + " written twice");
  FdBuffer buffer(out.fd);
  std::ostream os(&buffer);
  os.imbue(std::locale::classic());
  fill(os);
  os.flush();
  int error = buffer.error();
  if (error == 0 && !os) error = EIO;
  const int fd = out.fd;
  out.fd = -1;
  if (::close(fd) != 0 && error == 0) error = errno;  // NFS reports some write errors here only
  if (error != 0) cannot_write(out.path, errno_text(error));
  out.written = true;
}

void OutputFiles::commit() {
  for (const Impl::Output& out : impl_->outputs)
    if (!out.written) throw std::logic_error("OutputFiles::commit: output " + out.path + " not written");
  TemporaryRegistry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  if (r.closed) cannot_write(impl_->outputs.empty() ? std::string("output") : impl_->outputs[0].path,
                             "the process is being interrupted");
  std::string replaced;
  std::vector<Impl::Output*> order;
  for (bool last : {false, true})
    for (Impl::Output& out : impl_->outputs)
      if (out.last == last) order.push_back(&out);
  for (Impl::Output* o : order) {
    Impl::Output& out = *o;
    if (::rename(out.temporary.c_str(), out.target.c_str()) != 0) {
      const int error = errno;
      std::string reason = errno_text(error);
      if (!replaced.empty()) reason += "; already replaced: " + replaced;
      cannot_write(out.path, reason);  // the destructor removes the other temporary files
    }
    out.renamed = true;
    r.files.erase(out.id);
    replaced += (replaced.empty() ? "" : ", ") + out.path;
  }
  r.directories.erase(impl_->set_id);  // they hold the outputs now
  impl_->has_directories = false;
}

void OutputFiles::discard() noexcept {
  if (!impl_) return;
  TemporaryRegistry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  for (Impl::Output& out : impl_->outputs) {
    if (out.fd >= 0) ::close(out.fd);
    out.fd = -1;
    if (!out.renamed && r.files.erase(out.id) > 0) ::unlink(out.temporary.c_str());
  }
  if (impl_->has_directories) {
    const auto it = r.directories.find(impl_->set_id);
    if (it != r.directories.end()) {
      for (auto d = it->second.rbegin(); d != it->second.rend(); ++d) ::rmdir(d->c_str());  // only if empty
      r.directories.erase(it);
    }
    impl_->has_directories = false;
  }
}

void check_output_path(const std::string& path) {
  const std::string target = output_target(path);
  const fs::path parent = fs::path(target).parent_path();
  struct stat st {};
  if (::stat(parent.empty() ? "." : parent.c_str(), &st) != 0) cannot_write(path, errno_text(errno));
  if (!S_ISDIR(st.st_mode)) cannot_write(path, errno_text(ENOTDIR));
}

void remove_temporary_outputs() noexcept {
  TemporaryRegistry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  for (const auto& [id, file] : r.files) ::unlink(file.c_str());
  r.files.clear();
  for (const auto& [id, dirs] : r.directories)
    for (auto d = dirs.rbegin(); d != dirs.rend(); ++d) ::rmdir(d->c_str());
  r.directories.clear();
  r.closed = true;
}

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  OutputFiles files;
  const std::size_t i = files.add(path);
  files.write(i, write);
  files.commit();
}

void check_mesh_extension(const std::string& path) {
  const std::string ext = extension_of(path);
  if (ext != ".off" && ext != ".obj" && ext != ".ply" && ext != ".stl") unknown_format(path, ext);
}

void write_triangle_mesh(const TriangleSoup& soup, std::ostream& out, const std::string& format) {
  const std::string ext = lower(format.empty() || format[0] == '.' ? format : "." + format);
  void (*writer)(std::ostream&, const TriangleSoup&) = nullptr;
  if (ext == ".off") writer = write_off;
  else if (ext == ".obj") writer = write_obj;
  else if (ext == ".ply") writer = write_ply;
  else if (ext == ".stl") writer = write_stl;
  else unknown_format("(stream)", ext);
  check_indices(soup, "(stream)");
  out.imbue(std::locale::classic());
  out << std::setprecision(17);
  writer(out, soup);
}

void write_triangle_mesh(const TriangleSoup& soup, const std::string& path) {
  check_mesh_extension(path);
  check_indices(soup, path);
  const std::string ext = extension_of(path);
  write_file_atomically(path, [&](std::ostream& out) { write_triangle_mesh(soup, out, ext); });
}

void write_polylines(const std::vector<std::vector<Point3d>>& polylines, std::ostream& out) {
  out.imbue(std::locale::classic());
  out << std::setprecision(17);
  for (const auto& polyline : polylines) {
    out << polyline.size();
    for (const Point3d& p : polyline) out << ' ' << p[0] << ' ' << p[1] << ' ' << p[2];
    out << '\n';
  }
}

void write_polylines(const std::vector<std::vector<Point3d>>& polylines, const std::string& path) {
  write_file_atomically(path, [&](std::ostream& out) { write_polylines(polylines, out); });
}

// ================================================================== kernel conversions

template <class K> Mesh<K> mesh_from_soup(const TriangleSoup& soup, const std::string& name) {
  using Point = typename K::Point_3;
  using VI = typename Mesh<K>::Vertex_index;
  const std::size_t n = soup.points.size();
  std::vector<char> used(n, 0);
  for (std::size_t f = 0; f < soup.triangles.size(); ++f) {
    const auto& t = soup.triangles[f];
    for (std::size_t index : t) {
      if (index >= n)
        invalid(name, "face " + std::to_string(f) + " has a vertex index " + std::to_string(index) +
                          " out of range (mesh has " + std::to_string(n) + " vertices)");
      used[index] = 1;
    }
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      invalid(name, "face " + std::to_string(f) + " repeats vertex " + std::to_string(t[0] == t[1] ? t[0] : t[2]));
  }
  const auto nv = static_cast<std::size_t>(std::count(used.begin(), used.end(), 1));
  Mesh<K> mesh;
  mesh.reserve(static_cast<typename Mesh<K>::size_type>(nv),
               static_cast<typename Mesh<K>::size_type>(nv + soup.triangles.size()),
               static_cast<typename Mesh<K>::size_type>(soup.triangles.size()));
  std::vector<VI> vertex(n);
  for (std::size_t i = 0; i < n; ++i)
    if (used[i]) vertex[i] = mesh.add_vertex(Point(soup.points[i][0], soup.points[i][1], soup.points[i][2]));
  for (std::size_t f = 0; f < soup.triangles.size(); ++f) {
    const auto& t = soup.triangles[f];
    if (mesh.add_face(vertex[t[0]], vertex[t[1]], vertex[t[2]]) == Mesh<K>::null_face())
      invalid(name, "face " + std::to_string(f) + " cannot be added (non-manifold configuration)");
  }
  return mesh;
}

template <class K> void check_coordinate_range(const Mesh<K>& mesh, const std::string& name) {
  std::vector<Point3d> points;
  points.reserve(mesh.number_of_vertices());
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    points.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())});
  }
  check_coordinate_range(points, name);
}

template <class K> void check_coordinate_range(const std::vector<Polyline<K>>& curves, const std::string& name) {
  // Point by point: a copy of a curve of 10 million points in doubles took 240 MB.
  for (std::size_t i = 0; i < curves.size(); ++i) {
    const std::string curve_name = name + ": curve " + std::to_string(i);
    for (std::size_t j = 0; j < curves[i].size(); ++j) {
      const auto& p = curves[i][j];
      check_magnitude({CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}, j, curve_name, false);
    }
  }
}

template <class K> TriangleSoup soup_from_mesh(const Mesh<K>& mesh) {
  TriangleSoup soup;
  constexpr std::size_t none = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> index(mesh.num_vertices(), none);  // also counts removed vertices
  soup.points.reserve(mesh.number_of_vertices());
  for (auto v : mesh.vertices()) {
    index[static_cast<std::size_t>(v)] = soup.points.size();
    const auto& p = mesh.point(v);
    soup.points.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())});
  }
  soup.triangles.reserve(mesh.number_of_faces());
  for (auto f : mesh.faces()) {
    std::array<std::size_t, 3> t{};
    std::size_t k = 0;
    const auto h0 = mesh.halfedge(f);
    auto h = h0;
    do {
      if (k < 3) t[k] = index[static_cast<std::size_t>(mesh.target(h))];
      ++k;
      h = mesh.next(h);
    } while (h != h0 && k <= 3);
    if (k != 3)
      throw InvalidInput("soup_from_mesh: face " + std::to_string(static_cast<std::size_t>(f)) +
                         " is not a triangle");
    soup.triangles.push_back(t);
  }
  return soup;
}

template <class K> std::vector<Polyline<K>> to_kernel(const std::vector<std::vector<Point3d>>& polylines) {
  std::vector<Polyline<K>> result;
  result.reserve(polylines.size());
  for (const auto& polyline : polylines) {
    Polyline<K> out;
    out.reserve(polyline.size());
    for (const Point3d& p : polyline) out.emplace_back(p[0], p[1], p[2]);
    result.push_back(std::move(out));
  }
  return result;
}

template <class K> std::vector<std::vector<Point3d>> to_doubles(const std::vector<Polyline<K>>& polylines) {
  std::vector<std::vector<Point3d>> result;
  result.reserve(polylines.size());
  for (const auto& polyline : polylines) {
    std::vector<Point3d> out;
    out.reserve(polyline.size());
    for (const auto& p : polyline) out.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())});
    result.push_back(std::move(out));
  }
  return result;
}

#define SEAM_INSTANTIATE_IO(K)                                                                     \
  template Mesh<K> mesh_from_soup<K>(const TriangleSoup&, const std::string&); \
  template void check_coordinate_range<K>(const Mesh<K>&, const std::string&);                      \
  template void check_coordinate_range<K>(const std::vector<Polyline<K>>&, const std::string&);                     \
  template TriangleSoup soup_from_mesh<K>(const Mesh<K>&);                                         \
  template std::vector<Polyline<K>> to_kernel<K>(const std::vector<std::vector<Point3d>>&);        \
  template std::vector<std::vector<Point3d>> to_doubles<K>(const std::vector<Polyline<K>>&);

SEAM_INSTANTIATE_IO(Exact)
SEAM_INSTANTIATE_IO(Filtered)
SEAM_INSTANTIATE_IO(Float)

#undef SEAM_INSTANTIATE_IO

}  // namespace seam
