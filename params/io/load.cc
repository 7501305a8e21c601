#include "params/io/load.h"

#include "params/io/suggest.h"

#include <cmath>
#include <limits>

namespace scw::params::detail {

std::string Got(const YamlNode& n) {
  switch (n.kind) {
    case YamlNode::Kind::kNull:
      return "an empty value";
    case YamlNode::Kind::kSequence:
      return "a list " + Render(n);
    case YamlNode::Kind::kMap:
      return "a map";
    case YamlNode::Kind::kScalar:
      return std::string("the ") + ScalarTypeName(ClassifyScalar(n.text, n.quoted)) + " " +
             Render(n);
  }
  return "?";
}

namespace {

// Scalar → double with the ROS typing rules. Empty string on success.
std::string ScalarToDouble(const YamlNode& n, bool accept_int, double* out, bool* was_int) {
  *was_int = false;
  if (n.kind != YamlNode::Kind::kScalar) return "expected a number (double), got " + Got(n);
  const ScalarType t = ClassifyScalar(n.text, n.quoted);
  if (t == ScalarType::kDouble) {
    ParseDouble(n.text, out);
    if (!std::isfinite(*out)) return n.text + " is not a finite number";
    return "";
  }
  if (t == ScalarType::kInt) {
    long long i = 0;
    ParseInt(n.text, &i);
    *was_int = true;
    *out = static_cast<double>(i);
    if (accept_int) return "";
    return "expected a double, got the integer " + n.text + "; write " + n.text +
           ".0 (the car's node rejects an integer for a double parameter)";
  }
  return "expected a number (double), got " + Got(n);
}

}  // namespace

std::string LineSuffix(int line) {
  return line > 0 ? " (line " + std::to_string(line) + ")" : std::string();
}

std::string ConvertLeaf(const YamlNode& node, const Meta&, bool accept_int, double* out,
                        std::string* note) {
  bool was_int = false;
  std::string err = ScalarToDouble(node, accept_int, out, &was_int);
  if (err.empty() && was_int) *note = "integer literal " + node.text + " normalised to a double";
  return err;
}

std::string ConvertLeaf(const YamlNode& node, const Meta&, int* out) {
  if (node.kind != YamlNode::Kind::kScalar) return "expected an integer, got " + Got(node);
  const ScalarType t = ClassifyScalar(node.text, node.quoted);
  if (t != ScalarType::kInt) {
    if (t == ScalarType::kDouble)
      return "expected an integer, got the double " + node.text +
             " (write it without a decimal point: the car's node declares an integer)";
    return "expected an integer, got " + Got(node);
  }
  long long v = 0;
  ParseInt(node.text, &v);
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
    return node.text + " is out of the integer range";
  *out = static_cast<int>(v);
  return "";
}

std::string ConvertLeaf(const YamlNode& node, const Meta&, std::int64_t* out) {
  if (node.kind != YamlNode::Kind::kScalar) return "expected an integer, got " + Got(node);
  const ScalarType t = ClassifyScalar(node.text, node.quoted);
  if (t != ScalarType::kInt) {
    if (t == ScalarType::kDouble)
      return "expected an integer, got the double " + node.text +
             " (write it without a decimal point)";
    return "expected an integer, got " + Got(node);
  }
  long long v = 0;
  ParseInt(node.text, &v);
  *out = static_cast<std::int64_t>(v);
  return "";
}

std::string ConvertLeaf(const YamlNode& node, const Meta&, bool* out) {
  if (node.kind == YamlNode::Kind::kScalar && !node.quoted && ParseBool(node.text, out)) return "";
  return "expected true or false, got " + Got(node);
}

std::string ConvertLeaf(const YamlNode& node, const Meta& meta, bool accept_int,
                        std::vector<double>* out, std::string* note) {
  if (node.kind != YamlNode::Kind::kSequence)
    return "expected a list of doubles like [1.0, 2.0], got " + Got(node);
  if (node.items.empty()) {
    // Lists that may be empty are workspace-only (friction patches): no node key declares one.
    if (meta.min_size == 0) {
      out->clear();
      return "";
    }
    return "empty list: the car's node cannot load an empty array; give at least one element";
  }
  out->clear();
  bool any_int = false, any_double = false;
  for (std::size_t i = 0; i < node.items.size(); ++i) {
    const YamlNode& item = node.items[i];
    double x = 0;
    bool was_int = false;
    std::string err = ScalarToDouble(item, true, &x, &was_int);
    if (!err.empty()) return "element [" + std::to_string(i) + "]: " + err;
    (was_int ? any_int : any_double) = true;
    out->push_back(x);
  }
  if (any_int && any_double && !accept_int)
    return "mixes integer and double literals " + Render(node) +
           ": the ROS 2 parser rejects the whole file (\"Sequence should be of same type\"); "
           "write every element with a decimal point";
  if (any_int && !any_double && !accept_int)
    return "is a list of integers " + Render(node) +
           "; the car's node declares a list of doubles: write every element with a decimal "
           "point";
  if (any_int) *note = "integer literal(s) in " + Render(node) + " normalised to doubles";
  return "";
}

std::string ConvertLeaf(const YamlNode& node, const Meta&, std::string* out) {
  if (node.kind != YamlNode::Kind::kScalar) return "expected a text value, got " + Got(node);
  *out = node.text;
  return "";
}

std::string ConvertLeaf(const YamlNode& node, const Meta&, std::vector<std::string>* out) {
  if (node.kind != YamlNode::Kind::kSequence)
    return "expected a list like [a, b], got " + Got(node);
  out->clear();
  for (std::size_t i = 0; i < node.items.size(); ++i) {
    const YamlNode& item = node.items[i];
    if (item.kind != YamlNode::Kind::kScalar)
      return "element [" + std::to_string(i) + "]: expected a text value, got " + Got(item);
    out->push_back(item.text);
  }
  return "";
}

const YamlNode* FindNode(const YamlNode* map, const std::string& path) {
  if (!map || map->kind != YamlNode::Kind::kMap) return nullptr;
  const YamlNode* found = nullptr;
  for (const auto& [key, value] : map->entries) {
    if (key == path) {
      found = &value;
    } else if (path.size() > key.size() && path.compare(0, key.size(), key) == 0 &&
               path[key.size()] == '.') {
      if (const YamlNode* deeper = FindNode(&value, path.substr(key.size() + 1))) found = deeper;
    }
  }
  return found;
}

std::string SuggestKey(const std::string& unknown, const std::vector<std::string>& known) {
  const std::vector<std::string_view> candidates(known.begin(), known.end());
  std::string best =
      ClosestWord(unknown, candidates, std::max<std::size_t>(3, unknown.size() / 5) + 1);
  if (!best.empty()) return best;
  // A key without its unit suffix (`abort.max_sideslip` for `abort.max_sideslip_deg`): the
  // known key that is the unknown one plus `_` and one word.
  for (const auto& k : known)
    if (k.size() > unknown.size() + 1 && k.compare(0, unknown.size(), unknown) == 0 &&
        k[unknown.size()] == '_' &&
        k.find_first_of("._", unknown.size() + 1) == std::string::npos &&
        (best.empty() || k.size() < best.size()))
      best = k;
  return best;
}

}  // namespace scw::params::detail
