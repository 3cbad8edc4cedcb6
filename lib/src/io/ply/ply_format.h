// tear: a PLY file's header and the values of its data section, for the PLY reader (read_ply.cpp).
#pragma once

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "tear/error.h"

namespace tear::ply {

enum class PlyType { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

inline std::size_t size_of(PlyType type) {
  switch (type) {
    case PlyType::int8:
    case PlyType::uint8:
      return 1;
    case PlyType::int16:
    case PlyType::uint16:
      return 2;
    case PlyType::int32:
    case PlyType::uint32:
    case PlyType::float32:
      return 4;
    case PlyType::float64:
      return 8;
  }
  return 1;
}

inline bool is_integer(PlyType type) { return type != PlyType::float32 && type != PlyType::float64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::float32;  ///< the value type, or a list's item type
  bool list = false;
  PlyType count_type = PlyType::uint8;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;

  int find(const char* property) const {
    for (std::size_t i = 0; i < properties.size(); ++i) {
      if (properties[i].name == property) return static_cast<int>(i);
    }
    return -1;
  }
};

enum class PlyFormat { ascii, binary_little_endian, binary_big_endian };

/// Header text quoted in a message: printable ASCII only, and short.
std::string printable(const std::string& text);

struct PlyHeader {
  PlyFormat format = PlyFormat::ascii;
  std::vector<PlyElement> elements;
  std::size_t data_begin = 0;  ///< offset of the first byte after `end_header`'s line
};

/// The header of the PLY file `bytes`: its format, elements and properties, and where its data
/// begins. Throws an input `Error` naming `path` and the header line.
PlyHeader parse_header(const std::string& path, const std::string& bytes);

/// Every element's instances need at least this many bytes (binary) or values (ASCII); their sum
/// over the file must fit in the data it has, or the counts are lies and nothing is allocated.
void check_counts(const std::string& path, const PlyHeader& header, std::size_t data_bytes);

template <typename T>
inline double load(const unsigned char* raw) {
  T value;
  std::memcpy(&value, raw, sizeof value);
  return static_cast<double>(value);
}

/// A binary value of `type` at `at`, as a double (exact for every PLY type).
inline double decode(const char* at, PlyType type, bool big_endian) {
  unsigned char raw[8];
  const std::size_t size = size_of(type);
  std::memcpy(raw, at, size);
  if (big_endian) std::reverse(raw, raw + size);
  // In the order of PlyType.
  static constexpr double (*const loaders[])(const unsigned char*) = {
      load<std::int8_t>,  load<std::uint8_t>,  load<std::int16_t>, load<std::uint16_t>,
      load<std::int32_t>, load<std::uint32_t>, load<float>,        load<double>};
  return loaders[static_cast<int>(type)](raw);
}

/// Reads the values of the data section one by one, binary or ASCII, and fails with the element
/// and instance it was reading when the file ends or a value is malformed.
class PlyReader {
 public:
  PlyReader(const std::string& path, const std::string& bytes, const PlyHeader& header)
      : path_(path), p_(bytes.data() + header.data_begin), end_(bytes.data() + bytes.size()), format_(header.format) {}

  void at(const PlyElement& element, std::uint64_t instance) {
    element_ = &element;
    instance_ = instance;
  }

  std::size_t bytes_left() const { return static_cast<std::size_t>(end_ - p_); }
  bool ascii() const { return format_ == PlyFormat::ascii; }

  /// The next value, of `type`, as a double (exact for every PLY type).
  double next(PlyType type, const std::string& property) {
    return ascii() ? next_text(type, property) : next_binary(type, property);
  }

  /// A list's count: a non-negative integer whose items fit in what is left of the file.
  std::uint64_t next_count(const PlyProperty& property) {
    const double count = next(property.count_type, property.name);
    if (count < 0) throw fail("'" + property.name + "' has a negative count");
    const std::uint64_t items = static_cast<std::uint64_t>(count);
    // Each item needs its bytes, or in ASCII at least one character and a separator.
    const std::uint64_t least = ascii() ? 1 : size_of(property.type);
    if (items > bytes_left() / least + 1)
      throw fail("'" + property.name + "' has " + std::to_string(items) +
                 " items, more than the rest of the file holds");
    return items;
  }

  /// The next `bytes` bytes of a binary file, which the caller has checked are there.
  const char* take(std::size_t bytes) {
    const char* at = p_;
    p_ += bytes;
    return at;
  }
  bool big_endian() const { return format_ == PlyFormat::binary_big_endian; }

  Error fail(const std::string& what) const {
    return input_error(path_, element_->name + " " + std::to_string(instance_) + ": " + what);
  }

 private:
  double next_binary(PlyType type, const std::string& property) {
    const std::size_t size = size_of(type);
    if (bytes_left() < size) throw fail("the file ends in '" + property + "' (truncated)");
    return decode(take(size), type, format_ == PlyFormat::binary_big_endian);
  }

  double next_text(PlyType type, const std::string& property) {
    auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
    while (p_ < end_ && space(*p_)) ++p_;
    const char* first = p_;
    while (p_ < end_ && !space(*p_)) ++p_;
    if (first == p_) throw fail("the file ends before '" + property + "' (truncated)");
    const char* const token = first;
    if (*first == '+') ++first;  // from_chars takes no plus sign
    if (is_integer(type)) {
      std::int64_t value = 0;
      const auto parsed = std::from_chars(first, p_, value);
      if (parsed.ec == std::errc() && parsed.ptr == p_) {
        check_range(type, static_cast<double>(value), property);
        return static_cast<double>(value);
      }
      double wide = 0.0;
      const auto wide_parsed = std::from_chars(first, p_, wide);
      if (wide_parsed.ec != std::errc() || wide_parsed.ptr != p_ || wide != std::floor(wide)) {
        throw fail("'" + property + "' is not an integer: '" + printable(std::string(token, p_)) + "'");
      }
      check_range(type, wide, property);
      return wide;
    }
    // Floats are parsed at their own precision, so a float written with 9 digits reads back exactly.
    if (type == PlyType::float32) {
      float value = 0.0f;
      const auto parsed = std::from_chars(first, p_, value);
      if (parsed.ec == std::errc() && parsed.ptr == p_) return value;
    } else {
      double value = 0.0;
      const auto parsed = std::from_chars(first, p_, value);
      if (parsed.ec == std::errc() && parsed.ptr == p_) return value;
    }
    throw fail("'" + property + "' is not a number: '" + printable(std::string(token, p_)) + "'");
  }

  void check_range(PlyType type, double value, const std::string& property) const {
    double low = 0, high = 0;
    switch (type) {
      case PlyType::int8:
        low = -128;
        high = 127;
        break;
      case PlyType::uint8:
        high = 255;
        break;
      case PlyType::int16:
        low = -32768;
        high = 32767;
        break;
      case PlyType::uint16:
        high = 65535;
        break;
      case PlyType::int32:
        low = -2147483648.0;
        high = 2147483647.0;
        break;
      case PlyType::uint32:
        high = 4294967295.0;
        break;
      default:
        return;
    }
    if (value < low || value > high) throw fail("'" + property + "' is out of the range of its type");
  }

  std::string path_;
  const char* p_;
  const char* end_;
  PlyFormat format_;
  const PlyElement* element_ = nullptr;
  std::uint64_t instance_ = 0;
};

}  // namespace tear::ply
