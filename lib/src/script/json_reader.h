// tear: reading validated values out of parsed JSON, with errors that name the file and the key
// path ("shot.json: cuts[2].polyline[1]: expected an array of 2 numbers, got ..."). Shared by the
// cut script and its simulation block.
#pragma once

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tear/error.h"

namespace tear::json_reading {

using json = nlohmann::json;

/// A key that is a plain identifier; others are written as ["..."] in paths.
inline bool is_plain_key(const std::string& key) {
  if (key.empty() || std::isdigit(static_cast<unsigned char>(key[0]))) return false;
  return std::all_of(key.begin(), key.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-'; });
}

/// `s` as a JSON string literal, escaped so a message stays on one line.
inline std::string quoted(const std::string& s) { return json(s).dump(-1, ' ', false, json::error_handler_t::replace); }

inline std::string child_path(const std::string& parent, const std::string& key) {
  if (!is_plain_key(key)) return parent + "[" + quoted(key) + "]";
  return parent.empty() ? key : parent + "." + key;
}

inline std::string child_path(const std::string& parent, std::size_t index) {
  return parent + "[" + std::to_string(index) + "]";
}

inline std::string shown_path(const std::string& path) { return path.empty() ? "(root)" : path; }

/// What a value is, for "got ..." in messages: short and on one line.
inline std::string describe(const json& value) {
  switch (value.type()) {
    case json::value_t::null:
      return "null";
    case json::value_t::boolean:
      return value.get<bool>() ? "true" : "false";
    case json::value_t::string: {
      const auto& s = value.get_ref<const std::string&>();
      constexpr std::size_t longest = 40;
      return s.size() <= longest ? quoted(s) : quoted(s.substr(0, longest)) + "...";
    }
    case json::value_t::array:
      if (value.empty()) return "an empty array";
      return "an array of " + std::to_string(value.size()) + (value.size() == 1 ? " element" : " elements");
    case json::value_t::object:
      return value.empty() ? "an empty object" : "an object";
    default:
      if (value.is_number_float() && !std::isfinite(value.get<double>())) return "a non-finite number";
      return value.dump();
  }
}

/// Typed reads that throw an input `Error` naming the file and the key path.
class JsonReader {
 public:
  explicit JsonReader(const std::string& file) : file_(file) {}

  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw input_error(file_, shown_path(path) + ": " + what);
  }

  /// An object holding only `allowed` keys. Unknown keys are errors, so that a typo in a pipeline
  /// does not silently drop a cut or leave a default in place.
  void expect_object(const json& value, const std::string& path, const std::vector<std::string>& allowed) const {
    if (!value.is_object()) fail(path, "expected an object, got " + describe(value));
    for (const auto& item : value.items()) {
      if (std::find(allowed.begin(), allowed.end(), item.key()) != allowed.end()) continue;
      std::string list;
      for (std::size_t i = 0; i < allowed.size(); ++i)
        list += (i == 0 ? "" : i + 1 == allowed.size() ? " or " : ", ") + allowed[i];
      fail(child_path(path, item.key()), "unknown key (expected " + list + ")");
    }
  }

  const json& member(const json& object, const std::string& path, const std::string& key,
                     const std::string& expected) const {
    const auto it = object.find(key);
    if (it == object.end()) fail(child_path(path, key), "missing (expected " + expected + ")");
    return *it;
  }

  double number(const json& value, const std::string& path) const {
    if (!value.is_number()) fail(path, "expected a number, got " + describe(value));
    const double x = value.get<double>();
    if (!std::isfinite(x)) fail(path, "expected a finite number, got " + describe(value));
    return x;
  }

  /// A finite number with `ok(x)`, else "expected <expected>, got <value>".
  template <class Ok>
  double number(const json& value, const std::string& path, const std::string& expected, Ok ok) const {
    if (!value.is_number() || !std::isfinite(value.get<double>()) || !ok(value.get<double>()))
      fail(path, "expected " + expected + ", got " + describe(value));
    return value.get<double>();
  }

  /// JSON does not tell 4 from 4.0, and generators differ: any number with an integral value in
  /// [lo, hi] counts. Non-negative integers arrive as unsigned and are compared as such, or
  /// 2^64 - 1 would pass as -1.
  long long integer(const json& value, const std::string& path, long long lo, long long hi,
                    const std::string& expected) const {
    bool ok = false;
    long long n = 0;
    if (value.is_number_unsigned()) {
      const unsigned long long u = value.get<unsigned long long>();
      ok = u <= static_cast<unsigned long long>(hi) && static_cast<long long>(u) >= lo;
      n = static_cast<long long>(u);
    } else if (value.is_number_integer()) {
      n = value.get<long long>();
      ok = n >= lo && n <= hi;
    } else if (value.is_number_float()) {
      const double x = value.get<double>();
      ok = std::isfinite(x) && x == std::floor(x) && x >= static_cast<double>(lo) && x <= static_cast<double>(hi);
      if (ok) n = static_cast<long long>(x);
    }
    if (!ok) fail(path, "expected " + expected + ", got " + describe(value));
    return n;
  }

  /// An array of N finite numbers.
  template <std::size_t N>
  std::array<double, N> point(const json& value, const std::string& path) const {
    if (!value.is_array() || value.size() != N)
      fail(path, "expected an array of " + std::to_string(N) + " numbers, got " + describe(value));
    std::array<double, N> p{};
    for (std::size_t i = 0; i < N; ++i) p[i] = number(value[i], child_path(path, i));
    return p;
  }

  /// The file the messages name.
  const std::string& file() const { return file_; }

 private:
  const std::string& file_;
};

}  // namespace tear::json_reading
