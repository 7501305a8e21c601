// Byte encoding of the messages between the processes of an MPI run (tuning/exec/mpi_backend.h) and
// the worker processes (tuning/exec/processes.h): integers and doubles as their raw bytes (the
// processes run the same binary on the same kind of machine), strings with their length. A double
// travels bit for bit, so a parameter set or a result decoded on the other side is exactly the one
// encoded.
//
// Parameter structs go field by field through their schema visitor (params/schema/field.h), so
// no second list of their fields exists.
#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "params/schema/field.h"

namespace scw::tuning::exec {

class WireWriter {
 public:
  void Int(std::int64_t x) { Raw(&x, sizeof x); }
  void Double(double x) { Raw(&x, sizeof x); }
  void Bool(bool x) { bytes_.push_back(x ? '\1' : '\0'); }
  void String(std::string_view s) {
    Int(static_cast<std::int64_t>(s.size()));
    bytes_.append(s);
  }
  void Doubles(const std::vector<double>& v) {
    Int(static_cast<std::int64_t>(v.size()));
    for (double x : v) Double(x);
  }
  /// Every field of a parameter struct, in schema order.
  template <class P>
  void Params(const P& p) {
    params::ForEachField(
        p, [this](const std::string&, const auto& value, const params::Meta&) { Value(value); });
  }

  const std::string& bytes() const { return bytes_; }
  std::string Take() { return std::move(bytes_); }

 private:
  void Raw(const void* p, std::size_t n) { bytes_.append(static_cast<const char*>(p), n); }
  template <class T>
  void Value(const T& v) {
    if constexpr (std::is_same_v<T, double>)
      Double(v);
    else if constexpr (std::is_same_v<T, int>)
      Int(v);
    else if constexpr (std::is_same_v<T, bool>)
      Bool(v);
    else if constexpr (std::is_same_v<T, std::string>)
      String(v);
    else if constexpr (std::is_same_v<T, std::vector<double>>)
      Doubles(v);
    else
      static_assert(sizeof(T) == 0, "WireWriter: a field type without an encoding");
  }

  std::string bytes_;
};

/// Reads what a WireWriter wrote, in the same order; throws std::runtime_error when the bytes end
/// early or a length is impossible.
class WireReader {
 public:
  explicit WireReader(std::string_view bytes) : bytes_(bytes) {}

  std::int64_t Int() {
    std::int64_t x = 0;
    Raw(&x, sizeof x);
    return x;
  }
  double Double() {
    double x = 0.0;
    Raw(&x, sizeof x);
    return x;
  }
  bool Bool() {
    char c = 0;
    Raw(&c, 1);
    return c != '\0';
  }
  std::string String() {
    const std::size_t n = Length(1);
    std::string s(bytes_.substr(at_, n));
    at_ += n;
    return s;
  }
  std::vector<double> Doubles() {
    std::vector<double> v(Length(sizeof(double)));
    for (double& x : v) x = Double();
    return v;
  }
  template <class P>
  void Params(P* p) {
    params::ForEachField(
        *p, [this](const std::string&, auto& value, const params::Meta&) { Value(value); });
  }
  /// The bytes not read yet.
  std::string_view Rest() const { return bytes_.substr(at_); }
  bool AtEnd() const { return at_ == bytes_.size(); }

 private:
  void Raw(void* p, std::size_t n) {
    if (bytes_.size() - at_ < n) throw std::runtime_error("truncated message");
    std::memcpy(p, bytes_.data() + at_, n);
    at_ += n;
  }
  std::size_t Length(std::size_t unit) {
    const std::int64_t n = Int();
    if (n < 0 || static_cast<std::uint64_t>(n) > (bytes_.size() - at_) / unit)
      throw std::runtime_error("malformed message (bad length)");
    return static_cast<std::size_t>(n);
  }
  template <class T>
  void Value(T& v) {
    if constexpr (std::is_same_v<T, double>)
      v = Double();
    else if constexpr (std::is_same_v<T, int>)
      v = static_cast<int>(Int());
    else if constexpr (std::is_same_v<T, bool>)
      v = Bool();
    else if constexpr (std::is_same_v<T, std::string>)
      v = String();
    else if constexpr (std::is_same_v<T, std::vector<double>>)
      v = Doubles();
    else
      static_assert(sizeof(T) == 0, "WireReader: a field type without an encoding");
  }

  std::string_view bytes_;
  std::size_t at_ = 0;
};

}  // namespace scw::tuning::exec
