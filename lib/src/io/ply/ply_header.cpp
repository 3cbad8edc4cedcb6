// The PLY header: its lines parsed, and the counts it declares checked against the data the file has.
#include <charconv>
#include <cstdint>
#include <string>
#include <vector>

#include "io/ply/ply_format.h"
#include "tear/error.h"

namespace tear::ply {
namespace {

bool type_from_name(const std::string& name, PlyType& type) {
  static const struct {
    const char* name;
    PlyType type;
  } names[] = {{"char", PlyType::int8},      {"int8", PlyType::int8},       {"uchar", PlyType::uint8},
               {"uint8", PlyType::uint8},    {"short", PlyType::int16},     {"int16", PlyType::int16},
               {"ushort", PlyType::uint16},  {"uint16", PlyType::uint16},   {"int", PlyType::int32},
               {"int32", PlyType::int32},    {"uint", PlyType::uint32},     {"uint32", PlyType::uint32},
               {"float", PlyType::float32},  {"float32", PlyType::float32}, {"double", PlyType::float64},
               {"float64", PlyType::float64}};
  for (const auto& entry : names) {
    if (name == entry.name) {
      type = entry.type;
      return true;
    }
  }
  return false;
}

std::vector<std::string> split_words(const std::string& line) {
  std::vector<std::string> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    std::size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
    if (j > i) words.push_back(line.substr(i, j - i));
    i = j;
  }
  return words;
}

}  // namespace

std::string printable(const std::string& text) {
  std::string out;
  for (char c : text.substr(0, 40)) out += (c >= 0x20 && c < 0x7F) ? c : '?';
  return text.size() > 40 ? out + "..." : out;
}

PlyHeader parse_header(const std::string& path, const std::string& bytes) {
  auto fail = [&](std::size_t line, const std::string& what) {
    return input_error(path, "PLY header line " + std::to_string(line) + ": " + what);
  };
  PlyHeader header;
  bool have_format = false;
  std::size_t begin = 0, line_number = 0;
  while (true) {
    const std::size_t end = bytes.find('\n', begin);
    if (end == std::string::npos) throw input_error(path, "PLY header has no 'end_header' line");
    std::string line = bytes.substr(begin, end - begin);
    begin = end + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::vector<std::string> words = split_words(line);
    if (line_number == 1) {
      if (words.size() != 1 || words[0] != "ply")
        throw input_error(path, "not a PLY file (the first line is not 'ply')");
      continue;
    }
    if (words.empty()) continue;
    const std::string& keyword = words[0];
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") break;
    if (keyword == "format") {
      if (words.size() != 3 || words[2] != "1.0") throw fail(line_number, "expected 'format <type> 1.0'");
      if (words[1] == "ascii") {
        header.format = PlyFormat::ascii;
      } else if (words[1] == "binary_little_endian") {
        header.format = PlyFormat::binary_little_endian;
      } else if (words[1] == "binary_big_endian") {
        header.format = PlyFormat::binary_big_endian;
      } else {
        throw fail(line_number, "unknown format '" + printable(words[1]) + "'");
      }
      have_format = true;
    } else if (keyword == "element") {
      if (words.size() != 3) throw fail(line_number, "expected 'element <name> <count>'");
      PlyElement element;
      element.name = words[1];
      const char* first = words[2].data();
      const char* last = first + words[2].size();
      const auto parsed = std::from_chars(first, last, element.count);
      if (parsed.ec != std::errc() || parsed.ptr != last) {
        throw fail(line_number,
                   "element '" + printable(words[1]) + "' has no count (got '" + printable(words[2]) + "')");
      }
      header.elements.push_back(element);
    } else if (keyword == "property") {
      if (header.elements.empty()) throw fail(line_number, "a property before any element");
      PlyProperty property;
      if (words.size() == 5 && words[1] == "list") {
        property.list = true;
        if (!type_from_name(words[2], property.count_type) || !is_integer(property.count_type)) {
          throw fail(line_number, "a list count must be of an integer type, got '" + printable(words[2]) + "'");
        }
        if (!type_from_name(words[3], property.type))
          throw fail(line_number, "unknown type '" + printable(words[3]) + "'");
        property.name = words[4];
      } else if (words.size() == 3) {
        if (!type_from_name(words[1], property.type))
          throw fail(line_number, "unknown type '" + printable(words[1]) + "'");
        property.name = words[2];
      } else {
        throw fail(line_number, "expected 'property <type> <name>' or 'property list <type> <type> <name>'");
      }
      header.elements.back().properties.push_back(property);
    }
    // Any other line is taken as a comment, as other readers do (old Blender wrote its
    // "Created by" line without the keyword).
  }
  if (!have_format) throw input_error(path, "PLY header has no 'format' line");
  header.data_begin = begin;
  return header;
}

/// Every element's instances need at least this many bytes (binary) or values (ASCII); their sum
/// over the file must fit in the data it has, or the counts are lies and nothing is allocated.
void check_counts(const std::string& path, const PlyHeader& header, std::size_t data_bytes) {
  const bool ascii = header.format == PlyFormat::ascii;
  // In ASCII each value takes at least one character and one separator (the last may have none).
  const std::uint64_t available = ascii ? (static_cast<std::uint64_t>(data_bytes) + 1) / 2 : data_bytes;
  std::uint64_t needed = 0;
  for (const PlyElement& element : header.elements) {
    std::uint64_t least = 0;
    for (const PlyProperty& property : element.properties) {
      least += ascii ? 1 : size_of(property.list ? property.count_type : property.type);
    }
    if (least == 0) continue;
    if (element.count > (available - needed) / least) {
      throw input_error(path, "declares " + std::to_string(element.count) + " " + printable(element.name) +
                                  " elements, more than its " + std::to_string(data_bytes) +
                                  " bytes of data can hold (truncated or corrupt)");
    }
    needed += element.count * least;
  }
}

}  // namespace tear::ply
