// A YAML document read for strict parameter loading: every node keeps its source line, whether a
// scalar was quoted, and every map entry in file order INCLUDING duplicate keys (yaml-cpp's own
// tree silently keeps the first duplicate, the ROS 2 parser the last — we must see both).
// Flattening turns the nested maps below the parameter root into dotted keys, as rcl does.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "params/schema/field.h"

namespace scw::params {

struct YamlNode {
  enum class Kind { kNull, kScalar, kSequence, kMap };
  Kind kind = Kind::kNull;
  std::string text;             ///< scalar text
  bool quoted = false;          ///< scalar was single- or double-quoted (always a string for rcl)
  bool flow = false;            ///< sequence/map written in flow style
  int line = 0;                 ///< 1-based source line
  std::vector<YamlNode> items;  ///< sequence elements
  std::vector<std::pair<std::string, YamlNode>> entries;  ///< map entries (duplicates kept)

  // Defined out of line: an implicit (inline) default constructor makes clang instantiate
  // std::pair<std::string, YamlNode> while YamlNode is still incomplete (libstdc++ 12), which
  // breaks the clang builds (fuzzing, test/fuzz).
  YamlNode();
};

/// Type a plain (unquoted) scalar gets under the ROS 2 (rcl) rules; quoted scalars are strings.
enum class ScalarType { kBool, kInt, kDouble, kString };
const char* ScalarTypeName(ScalarType t);
ScalarType ClassifyScalar(const std::string& text, bool quoted);
/// Parses per rcl rules; false if the text is not of that type.
bool ParseBool(const std::string& text, bool* out);
bool ParseInt(const std::string& text, long long* out);
bool ParseDouble(const std::string& text, double* out);

/// Parses one YAML document. Throws ConfigError (file, line, message) on a syntax error, on an
/// anchor or alias (rejected by the ROS 2 parser), or on more than one document.
YamlNode ParseYaml(const std::string& text, const std::string& file);

/// Reads a file; throws ConfigError naming the file if it cannot be read.
std::string ReadTextFile(const std::string& path);

/// One leaf below the parameter root with its dotted key.
struct FlatEntry {
  std::string key;
  const YamlNode* node = nullptr;
};

enum class Layout {
  kRos2,   ///< `<node key>: ros__parameters: {...}` (the car's params file)
  kPlain,  ///< the root map holds the parameters directly
};

/// The parameter entries of a document in file order (duplicates kept), plus the problems found
/// while locating the parameter root.
struct FlatDoc {
  std::vector<FlatEntry> entries;
  const YamlNode* map = nullptr;  ///< the map the entries come from (maps a loader reads whole)
  std::string node_key;           ///< the node key found (kRos2)
  int root_line = 0;
};

/// Locates the parameter root for `layout` and flattens it. For kRos2 the node key must name
/// `expected_node` (nested `/ns: node:` and a missing leading '/' are accepted, wildcards are not);
/// an empty `expected_node` accepts the file's single node section, whatever its name.
FlatDoc Flatten(const YamlNode& root, Layout layout, const std::string& expected_node,
                Problems* problems);
/// The entries point into `root`: flattening a temporary would leave them dangling.
FlatDoc Flatten(YamlNode&& root, Layout layout, const std::string& expected_node,
                Problems* problems) = delete;

/// Short rendering of a node for messages: scalars verbatim, sequences as [a, b], maps as {…}.
std::string Render(const YamlNode& node);

}  // namespace scw::params
