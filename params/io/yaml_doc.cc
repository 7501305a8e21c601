#include "params/io/yaml_doc.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

namespace scw::params {

YamlNode::YamlNode() = default;

const char* ScalarTypeName(ScalarType t) {
  switch (t) {
    case ScalarType::kBool:
      return "bool";
    case ScalarType::kInt:
      return "integer";
    case ScalarType::kDouble:
      return "double";
    case ScalarType::kString:
      return "string";
  }
  return "?";
}

bool ParseBool(const std::string& t, bool* out) {
  static const char* kTrue[] = {"y",    "Y",    "yes", "Yes", "YES", "true",
                                "True", "TRUE", "on",  "On",  "ON"};
  static const char* kFalse[] = {"n",     "N",     "no",  "No",  "NO", "false",
                                 "False", "FALSE", "off", "Off", "OFF"};
  for (const char* w : kTrue)
    if (t == w) return *out = true, true;
  for (const char* w : kFalse)
    if (t == w) return *out = false, true;
  return false;
}

bool ParseInt(const std::string& t, long long* out) {
  if (t.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(t.c_str(), &end, 0);
  if (end != t.c_str() + t.size()) return false;
  if (errno == ERANGE) return false;
  *out = v;
  return true;
}

bool ParseDouble(const std::string& t, double* out) {
  if (t.empty()) return false;
  static const std::pair<const char*, double> kSpecial[] = {
      {".nan", std::nan("")}, {".NaN", std::nan("")}, {".NAN", std::nan("")}, {".inf", HUGE_VAL},
      {".Inf", HUGE_VAL},     {".INF", HUGE_VAL},     {"+.inf", HUGE_VAL},    {"+.Inf", HUGE_VAL},
      {"+.INF", HUGE_VAL},    {"-.inf", -HUGE_VAL},   {"-.Inf", -HUGE_VAL},   {"-.INF", -HUGE_VAL}};
  for (const auto& [w, v] : kSpecial)
    if (t == w) return *out = v, true;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size()) return false;
  *out = v;  // ERANGE: ±HUGE_VAL or a denormal; the finiteness check reports overflow
  return true;
}

ScalarType ClassifyScalar(const std::string& text, bool quoted) {
  if (quoted) return ScalarType::kString;
  bool b;
  long long i;
  double d;
  if (ParseBool(text, &b)) return ScalarType::kBool;
  if (ParseInt(text, &i)) return ScalarType::kInt;
  // strtoll overflow: rcl then tries strtod, which succeeds with a huge double.
  if (ParseDouble(text, &d)) return ScalarType::kDouble;
  return ScalarType::kString;
}

namespace {

class TreeBuilder : public YAML::EventHandler {
 public:
  /// `text`: the source (to tell `key:` from a bare `key`); may be empty.
  explicit TreeBuilder(std::string file, std::string_view text = {})
      : file_(std::move(file)), text_(text) {}

  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    CheckAnchor(mark, anchor);
    YamlNode n;
    n.kind = YamlNode::Kind::kNull;
    n.line = mark.line + 1;
    Add(std::move(n));
  }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override {
    throw ConfigError(file_, "",
                      "line " + std::to_string(mark.line + 1) +
                          ": aliases (*name) are not allowed: the ROS 2 parameter "
                          "parser rejects them");
  }
  void OnScalar(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t anchor,
                const std::string& value) override {
    CheckAnchor(mark, anchor);
    YamlNode n;
    n.kind = YamlNode::Kind::kScalar;
    n.text = value;
    n.quoted = (tag == "!");
    n.line = mark.line + 1;
    scalar_line_ = mark.line;
    scalar_column_ = mark.column;
    Add(std::move(n));
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value style) override {
    CheckAnchor(mark, anchor);
    YamlNode n;
    n.kind = YamlNode::Kind::kSequence;
    n.flow = style == YAML::EmitterStyle::Flow;
    n.line = mark.line + 1;
    stack_.push_back({std::move(n), std::string(), false});
  }
  void OnSequenceEnd() override { Close(); }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value style) override {
    CheckAnchor(mark, anchor);
    YamlNode n;
    n.kind = YamlNode::Kind::kMap;
    n.flow = style == YAML::EmitterStyle::Flow;
    n.line = mark.line + 1;
    stack_.push_back({std::move(n), std::string(), false});
  }
  void OnMapEnd() override { Close(); }
  void OnAnchor(const YAML::Mark& mark, const std::string& name) override {
    throw ConfigError(file_, "",
                      "line " + std::to_string(mark.line + 1) + ": anchor &" + name +
                          " is not allowed: the ROS 2 parameter parser rejects "
                          "anchors and aliases");
  }

  bool has_root() const { return has_root_; }
  YamlNode TakeRoot() { return std::move(root_); }

 private:
  struct Frame {
    YamlNode node;
    std::string pending_key;
    bool has_key;
  };

  void CheckAnchor(const YAML::Mark& mark, YAML::anchor_t anchor) {
    if (anchor != YAML::NullAnchor)
      throw ConfigError(file_, "",
                        "line " + std::to_string(mark.line + 1) +
                            ": anchors (&name) are not allowed: the ROS 2 "
                            "parameter parser rejects anchors and aliases");
  }
  void Close() {
    Frame f = std::move(stack_.back());
    stack_.pop_back();
    Add(std::move(f.node));
  }
  void Add(YamlNode n) {
    if (stack_.empty()) {
      root_ = std::move(n);
      has_root_ = true;
      return;
    }
    Frame& top = stack_.back();
    if (top.node.kind == YamlNode::Kind::kSequence) {
      top.node.items.push_back(std::move(n));
    } else if (!top.has_key) {
      if (n.kind != YamlNode::Kind::kScalar)
        throw ConfigError(file_, "",
                          "line " + std::to_string(n.line) + ": map keys must be plain scalars");
      if (!top.node.flow && !n.quoted) CheckColonAfterKey(n);
      top.pending_key = n.text;
      top.has_key = true;
    } else {
      top.node.entries.emplace_back(std::move(top.pending_key), std::move(n));
      top.has_key = false;
    }
  }

  /// A plain key of a block map must be followed by ':'. yaml-cpp reads a bare word at the end
  /// of a map (a file cut off mid-key) as a key without a value; rcl's libyaml refuses it, and so
  /// do we, as the syntax error it is, rather than as an unknown key and missing keys.
  void CheckColonAfterKey(const YamlNode& key) const {
    if (text_.empty() || scalar_line_ < 0 || scalar_column_ < 0) return;
    // By line and column (yaml-cpp's character offset need not be a byte offset).
    std::size_t pos = 0;
    for (int l = 0; l < scalar_line_; ++l) {
      pos = text_.find('\n', pos);
      if (pos == std::string_view::npos) return;
      ++pos;
    }
    pos += static_cast<std::size_t>(scalar_column_);
    if (pos + key.text.size() > text_.size() || text_.compare(pos, key.text.size(), key.text) != 0)
      return;  // a multi-line or escaped key: its source differs from its text; not checked
    std::size_t i = pos + key.text.size();
    while (i < text_.size() && (text_[i] == ' ' || text_[i] == '\t')) ++i;
    if (i < text_.size() && text_[i] == ':') return;
    throw ConfigError(file_, "",
                      "line " + std::to_string(key.line) + ": YAML syntax error: '" + key.text +
                          "' is not followed by ':' (a key without its value: is the file cut "
                          "off or the line incomplete?)");
  }

  std::string file_;
  std::string_view text_;
  int scalar_line_ = -1;  ///< 0-based position of the last scalar
  int scalar_column_ = -1;
  std::vector<Frame> stack_;
  YamlNode root_;
  bool has_root_ = false;
};

void FlattenInto(const YamlNode& map, const std::string& prefix, FlatDoc* out) {
  for (const auto& [key, value] : map.entries) {
    std::string path = JoinKey(prefix, key);
    if (value.kind == YamlNode::Kind::kMap) {
      FlattenInto(value, path, out);
    } else {
      out->entries.push_back({std::move(path), &value});
    }
  }
}

std::string NormalizeNode(std::string name) {
  if (name.empty() || name[0] != '/') name.insert(name.begin(), '/');
  return name;
}

}  // namespace

YamlNode ParseYaml(const std::string& text, const std::string& file) {
  const auto nul = text.find('\0');
  if (nul != std::string::npos)
    throw ConfigError(file, "",
                      "line " +
                          std::to_string(1 + std::count(text.begin(), text.begin() + nul, '\n')) +
                          ": a NUL byte: this is a binary file, not YAML text");
  std::istringstream in(text);
  TreeBuilder builder(file, text);
  try {
    YAML::Parser parser(in);
    if (!parser.HandleNextDocument(builder)) {
      return YamlNode{};  // empty document
    }
    TreeBuilder extra(file);
    if (parser.HandleNextDocument(extra) && extra.has_root())
      throw ConfigError(file, "", "more than one YAML document ('---'); a params file holds one");
  } catch (const YAML::Exception& e) {
    // Characters the terminal would not show (a binary file) as \xNN.
    std::string msg;
    for (const char c : e.msg) {
      const auto u = static_cast<unsigned char>(c);
      if (u >= 0x20 && u < 0x7f) {
        msg += c;
      } else {
        char hex[8];
        std::snprintf(hex, sizeof hex, "\\x%02X", static_cast<unsigned>(u));
        msg += hex;
      }
    }
    if (!e.mark.is_null())
      msg = "line " + std::to_string(e.mark.line + 1) + ", column " +
            std::to_string(e.mark.column + 1) + ": YAML syntax error: " + msg;
    else
      msg = "YAML syntax error: " + msg;
    throw ConfigError(file, "", msg);
  }
  return builder.TakeRoot();
}

std::string ReadTextFile(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw ConfigError(path, "", "is a directory, not a file");
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int error = errno;
    throw ConfigError(
        path, "",
        "cannot open the file for reading" +
            (error != 0 ? " (" + std::string(std::strerror(error)) + ")" : std::string()));
  }
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) throw ConfigError(path, "", "error while reading the file");
  return s.str();
}

FlatDoc Flatten(const YamlNode& root, Layout layout, const std::string& expected_node,
                Problems* problems) {
  FlatDoc doc;
  doc.root_line = root.line;
  if (root.kind == YamlNode::Kind::kNull) {
    problems->Add("", "the file is empty");
    return doc;
  }
  if (root.kind != YamlNode::Kind::kMap) {
    problems->Add("", "the top level must be a map of keys");
    return doc;
  }
  if (layout == Layout::kPlain) {
    doc.map = &root;
    FlattenInto(root, "", &doc);
    return doc;
  }
  // ROS 2 layout: walk the node-name maps until ros__parameters.
  const std::string want = expected_node.empty() ? std::string() : NormalizeNode(expected_node);
  bool found = false;
  std::vector<std::string> other_nodes;
  struct Walk {
    const YamlNode* map;
    std::string name;
  };
  std::vector<Walk> todo{{&root, ""}};
  while (!todo.empty()) {
    Walk w = todo.back();
    todo.pop_back();
    for (auto it = w.map->entries.rbegin(); it != w.map->entries.rend(); ++it) {
      const auto& [key, value] = *it;
      if (key == "ros__parameters") {
        const std::string name = NormalizeNode(w.name);
        if (!want.empty() && name != want) {
          other_nodes.push_back(name);
          continue;
        }
        if (value.kind != YamlNode::Kind::kMap) {
          problems->Add("ros__parameters",
                        "must be a map of parameters (line " + std::to_string(value.line) + ")");
          continue;
        }
        if (found)
          problems->Add("ros__parameters",
                        (want.empty() ? "more than one node section (" + doc.node_key + ", " +
                                            name + "); name the node to read"
                                      : "the node key " + want + " appears more than once") +
                            " (line " + std::to_string(value.line) + ")");
        found = true;
        doc.node_key = name;
        doc.root_line = value.line;
        doc.map = &value;
        FlattenInto(value, "", &doc);
      } else if (value.kind == YamlNode::Kind::kMap) {
        std::string name = w.name.empty() ? key : w.name + "/" + key;
        // "/core/control:" then "StabilityController:" — joined with one slash.
        while (name.find("//") != std::string::npos) name.erase(name.find("//"), 1);
        todo.push_back({&value, name});
      } else {
        problems->Add(key, "unexpected top-level entry (line " + std::to_string(value.line) +
                               "): a params file holds `<node name>: ros__parameters: {...}`");
      }
    }
  }
  if (!found) {
    std::string msg = want.empty() ? std::string("no `<node name>: ros__parameters:` section")
                                   : "no `" + want + ": ros__parameters:` section";
    if (!other_nodes.empty()) {
      msg += " (found node key(s):";
      for (const auto& n : other_nodes) msg += " " + n;
      msg += ")";
      for (const auto& n : other_nodes)
        if (n.find('*') != std::string::npos) {
          msg +=
              "; wildcard node keys do not satisfy the car's parameter manager, which "
              "requires the exact node name";
          break;
        }
    }
    problems->Add("", msg);
  }
  return doc;
}

std::string Render(const YamlNode& node) {
  switch (node.kind) {
    case YamlNode::Kind::kNull:
      return "(empty)";
    case YamlNode::Kind::kScalar:
      return node.quoted ? "\"" + node.text + "\"" : node.text;
    case YamlNode::Kind::kSequence: {
      std::string s = "[";
      for (std::size_t i = 0; i < node.items.size(); ++i) {
        if (i) s += ", ";
        s += Render(node.items[i]);
      }
      return s + "]";
    }
    case YamlNode::Kind::kMap:
      return "{...}";
  }
  return "?";
}

}  // namespace scw::params
