#include "camera/storage_precheck.hpp"

#include <fmt/format.h>

#include <regex>
#include <string_view>

#include "spinewatch/frames/printable.hpp"

namespace spinewatch {
namespace {

// OpenCV 4.6's YAML reader never returns on many malformed files: the
// calibration_yaml fuzzer found "%YAML:1.0\n-----0\n-\n",
// "%YAML:1.0\n a: o\nf---\n", "%YAML:1.0\n L:0\nxo--\n" and
// "%YAML:1.\n a:]\n--\n-" first, then ten more in ten minutes once those
// were refused (stray dashes, "%" and bytes in odd places). Refusing each
// shape as it is found is a race the fuzzer wins, so YAML is taken only in
// the line forms OpenCV's own writer produces and its calibration samples
// use:
//   %YAML:1.0                  the directive, first line only
//   ---                        the document marker
//   key:                       a map opens
//   key: !!opencv-matrix       a matrix opens (or !!opencv-nd-matrix)
//   key: 3 | d | "text"        a number, a word or a quoted string
//   key: [ 1., 0., -2.5e-01,   a flow of numbers, maybe over several lines
//      0., 1. ]                ... continued
//   # a comment, or a blank line
// with spaces for indentation. Everything OpenCV writes for a calibration
// is among these (tests/estimator/camera/camera_test.cpp reads files from
// OpenCV's samples and from cv::FileStorage's own writer).
constexpr std::size_t kMaxLine = 512;
constexpr std::string_view kNumber = R"([-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?|[-+]?\.(?:Inf|inf|NaN|nan))";

const std::regex& key_line() {
  static const std::regex re(R"(( *)[A-Za-z_][A-Za-z0-9_]*:(?: +(.*))?)");
  return re;
}
const std::regex& scalar_value() {
  static const std::regex re(std::string(R"(!!opencv-(?:nd-)?matrix|"[^"\\]*"|[A-Za-z0-9_.+-]+|)") +
                             std::string(kNumber));
  return re;
}
// The items of a flow of numbers, with or without its opening "[" and
// closing "]": "[ 1., 2.,", "3., 4. ]", "[]".
const std::regex& flow_items() {
  static const std::string n(kNumber);
  static const std::regex re(R"(\[? *(?:(?:)" + n + R"() *, *)*(?:)" + n + R"()? *,? *\]?)");
  return re;
}

Error bad_line(const std::string& file, std::size_t line, std::string_view text, std::string_view why) {
  return Error{fmt::format("{}: line {}: \"{}\": {}", file, line, printable(text.substr(0, 24)), why)};
}

Status check_yaml_lines(const std::string& text, const std::string& file) {
  bool in_flow = false;  // inside "[ ... ]" begun on an earlier line
  std::size_t line = 1;
  for (std::size_t at = 0; at < text.size(); ++line) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    const std::string_view raw(text.data() + at, end - at);
    at = end + 1;
    const std::string_view l = raw.substr(0, raw.find_last_not_of(" \r") + 1);
    // std::regex matches recursively, a frame per character: a line is
    // bounded before it is matched (OpenCV wraps its flows near 80).
    if (raw.size() > kMaxLine)
      return bad_line(file, line, raw, fmt::format("longer than {} characters", kMaxLine));
    const std::size_t first = l.find_first_not_of(' ');
    if (first == std::string_view::npos || l[first] == '#') continue;
    // Two dashes have their own message: the first shapes found all held them.
    if (l.find("--") != std::string_view::npos && l != "---")
      return bad_line(file, line, raw, "\"--\" only in a \"---\" document marker on a line of its own");
    for (const char c : l)
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e)
        return bad_line(file, line, raw, "a tab, control or non-ASCII byte outside a comment");
    if (line == 1 && (l.rfind("%YAML:", 0) == 0 || l.rfind("%YAML ", 0) == 0) &&
        std::regex_match(l.begin() + 6, l.end(), std::regex(R"(1\.[0-9]*)")))
      continue;
    if (l == "---") continue;
    if (in_flow) {
      if (!std::regex_match(l.begin() + static_cast<std::ptrdiff_t>(first), l.end(), flow_items()) ||
          l[first] == '[')
        return bad_line(file, line, raw, "expected the numbers of a \"[ ... ]\" flow");
      in_flow = l.back() != ']';
      continue;
    }
    std::match_results<std::string_view::const_iterator> m;
    if (!std::regex_match(l.begin(), l.end(), m, key_line()))
      return bad_line(file, line, raw,
                      "not a line of OpenCV's YAML (\"key:\", \"key: value\", \"key: [ numbers ]\", a comment)");
    if (!m[2].matched) continue;
    const std::string_view value(&*m[2].first, static_cast<std::size_t>(m[2].length()));
    if (value.front() == '[') {
      if (!std::regex_match(value.begin(), value.end(), flow_items()))
        return bad_line(file, line, raw, "a \"[ ... ]\" flow holds numbers only");
      in_flow = value.back() != ']';
      continue;
    }
    if (!std::regex_match(value.begin(), value.end(), scalar_value()))
      return bad_line(file, line, raw, "a value is a number, a word, a \"quoted string\" or !!opencv-matrix");
  }
  if (in_flow) return Error{fmt::format("{}: a \"[ ... ]\" flow is not closed by the end of the file", file)};
  return Ok{};
}

}  // namespace

// OpenCV's XML reader dereferences null on a header as short as "<?xml e="
// (the calibration_yaml fuzzer): XML is taken only where allowed and only
// after a whole `<?xml version="…"?>` declaration. JSON is never taken,
// nor a NUL byte. Loops in OpenCV's XML reader may remain: docs/testing.md,
// "Fuzzing".
Status check_before_opencv(const std::string& text, const std::string& file, StorageFormats formats) {
  const std::size_t first = text.find_first_not_of(" \t\r\n");
  const char opening = first == std::string::npos ? '\0' : text[first];
  if ((opening == '<' || opening == '{') && formats == StorageFormats::YamlOnly)
    return Error{fmt::format("{}: XML or JSON storage; calibration.yaml is read as YAML only", file)};
  if (opening == '{') return Error{fmt::format("{}: JSON storage; read as YAML or XML only", file)};
  if (text.find('\0') != std::string::npos) return Error{fmt::format("{}: a NUL byte: not a text file", file)};
  if (opening == '<') {
    const std::size_t line_end = std::min(text.find('\n', first), text.size());
    const std::string_view declaration(text.data() + first, line_end - first);
    if (declaration.rfind("<?xml version=\"", 0) != 0 || declaration.find("?>") == std::string_view::npos)
      return Error{fmt::format("{}: XML without a whole <?xml version=\"1.0\"?> declaration on its first line", file)};
    return Ok{};
  }
  return check_yaml_lines(text, file);
}

}  // namespace spinewatch
