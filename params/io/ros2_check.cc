#include "params/io/ros2_check.h"

#include <yaml.h>

#include <cmath>
#include <map>
#include <memory>
#include <set>

#include "params/io/yaml_doc.h"

namespace scw::params {

const char* ParamTypeName(ParamType t) {
  switch (t) {
    case ParamType::kBool:
      return "bool";
    case ParamType::kInt:
      return "integer";
    case ParamType::kDouble:
      return "double";
    case ParamType::kDoubleArray:
      return "double array";
    case ParamType::kString:
      return "string";
  }
  return "?";
}

bool CheckReport::ok() const { return errors() == 0; }
int CheckReport::errors() const {
  int n = 0;
  for (const auto& f : findings) n += f.error;
  return n;
}
int CheckReport::warnings() const { return static_cast<int>(findings.size()) - errors(); }

std::string CheckReport::Format(const std::string& file) const {
  std::string out;
  for (const auto& f : findings) {
    out += file;
    if (f.line > 0) out += ":" + std::to_string(f.line);
    out += f.error ? ": error: " : ": warning: ";
    if (!f.key.empty()) out += f.key + ": ";
    out += f.message + "\n";
  }
  return out;
}

namespace {

struct ParserGuard {
  yaml_parser_t parser;
  ParserGuard() { yaml_parser_initialize(&parser); }
  ~ParserGuard() { yaml_parser_delete(&parser); }
};
struct EventGuard {
  yaml_event_t event;
  bool live = false;
  ~EventGuard() {
    if (live) yaml_event_delete(&event);
  }
};

struct ParseFailure {
  std::string message;
  int line;
};

// Builds a YamlNode tree from libyaml events; returns false with `failure` set on any error.
bool BuildTree(const std::string& text, YamlNode* root, ParseFailure* failure) {
  ParserGuard pg;
  yaml_parser_set_input_string(&pg.parser, reinterpret_cast<const unsigned char*>(text.data()),
                               text.size());
  struct Frame {
    YamlNode node;
    std::string key;
    bool has_key = false;
  };
  std::vector<Frame> stack;
  bool have_root = false;
  int documents = 0;
  auto add = [&](YamlNode n) -> bool {
    if (stack.empty()) {
      *root = std::move(n);
      have_root = true;
      return true;
    }
    Frame& top = stack.back();
    if (top.node.kind == YamlNode::Kind::kSequence) {
      top.node.items.push_back(std::move(n));
    } else if (!top.has_key) {
      if (n.kind != YamlNode::Kind::kScalar) {
        *failure = {"map keys must be scalars", n.line};
        return false;
      }
      top.key = n.text;
      top.has_key = true;
    } else {
      top.node.entries.emplace_back(std::move(top.key), std::move(n));
      top.has_key = false;
    }
    return true;
  };
  while (true) {
    EventGuard eg;
    if (!yaml_parser_parse(&pg.parser, &eg.event)) {
      *failure = {std::string("YAML syntax error: ") +
                      (pg.parser.problem ? pg.parser.problem : "unknown") +
                      (pg.parser.context ? std::string(" ") + pg.parser.context : std::string()),
                  static_cast<int>(pg.parser.problem_mark.line) + 1};
      return false;
    }
    eg.live = true;
    const int line = static_cast<int>(eg.event.start_mark.line) + 1;
    switch (eg.event.type) {
      case YAML_STREAM_END_EVENT:
        if (!have_root) *root = YamlNode{};
        return true;
      case YAML_DOCUMENT_START_EVENT:
        if (++documents > 1) {
          *failure = {"more than one YAML document", line};
          return false;
        }
        break;
      case YAML_ALIAS_EVENT:
        *failure = {"alias found: the ROS 2 parser will not support aliasing", line};
        return false;
      case YAML_SCALAR_EVENT: {
        if (eg.event.data.scalar.anchor) {
          *failure = {"anchor found: the ROS 2 parser will not support aliasing", line};
          return false;
        }
        YamlNode n;
        n.kind = YamlNode::Kind::kScalar;
        n.text.assign(reinterpret_cast<const char*>(eg.event.data.scalar.value),
                      eg.event.data.scalar.length);
        n.quoted = eg.event.data.scalar.style != YAML_PLAIN_SCALAR_STYLE;
        if (!n.quoted && n.text.empty()) n.kind = YamlNode::Kind::kNull;
        n.line = line;
        if (!add(std::move(n))) return false;
        break;
      }
      case YAML_SEQUENCE_START_EVENT:
      case YAML_MAPPING_START_EVENT: {
        const bool seq = eg.event.type == YAML_SEQUENCE_START_EVENT;
        if (seq ? eg.event.data.sequence_start.anchor : eg.event.data.mapping_start.anchor) {
          *failure = {"anchor found: the ROS 2 parser will not support aliasing", line};
          return false;
        }
        Frame f;
        f.node.kind = seq ? YamlNode::Kind::kSequence : YamlNode::Kind::kMap;
        f.node.line = line;
        stack.push_back(std::move(f));
        break;
      }
      case YAML_SEQUENCE_END_EVENT:
      case YAML_MAPPING_END_EVENT: {
        YamlNode n = std::move(stack.back().node);
        stack.pop_back();
        if (!add(std::move(n))) return false;
        break;
      }
      default:
        break;
    }
  }
}

ParamType LiteralType(const YamlNode& n, std::string* problem) {
  if (n.kind == YamlNode::Kind::kSequence) {
    if (n.items.empty()) {
      *problem = "empty array: the node cannot declare a parameter from an empty array";
      return ParamType::kDoubleArray;
    }
    std::set<ScalarType> types;
    for (const auto& item : n.items) {
      if (item.kind != YamlNode::Kind::kScalar) {
        *problem = "arrays may only hold scalars (no nested arrays or maps)";
        return ParamType::kDoubleArray;
      }
      types.insert(ClassifyScalar(item.text, item.quoted));
    }
    if (types.size() > 1) {
      *problem = "Sequence should be of same type: " + Render(n) +
                 " mixes literal types; the ROS 2 parser rejects the whole file";
      return ParamType::kDoubleArray;
    }
    switch (*types.begin()) {
      case ScalarType::kDouble:
        return ParamType::kDoubleArray;
      default:
        *problem =
            std::string("array of ") + ScalarTypeName(*types.begin()) + " literals " + Render(n);
        return ParamType::kString;  // never equals a declared double array
    }
  }
  switch (ClassifyScalar(n.text, n.quoted)) {
    case ScalarType::kBool:
      return ParamType::kBool;
    case ScalarType::kInt:
      return ParamType::kInt;
    case ScalarType::kDouble:
      return ParamType::kDouble;
    case ScalarType::kString:
      return ParamType::kString;
  }
  return ParamType::kString;
}

void Collect(const YamlNode& map, const std::string& prefix,
             std::vector<std::pair<std::string, const YamlNode*>>* out) {
  for (const auto& [k, v] : map.entries) {
    const std::string key = JoinKey(prefix, k);
    if (v.kind == YamlNode::Kind::kMap)
      Collect(v, key, out);
    else
      out->emplace_back(key, &v);
  }
}

}  // namespace

CheckReport CheckRosParamsText(const std::string& text, const std::vector<DeclaredParam>& declared,
                               const CheckOptions& options) {
  CheckReport rep;
  auto error = [&](std::string key, std::string msg, int line) {
    rep.findings.push_back({true, std::move(key), std::move(msg), line});
  };
  auto warn = [&](std::string key, std::string msg, int line) {
    rep.findings.push_back({false, std::move(key), std::move(msg), line});
  };
  if (text.find('\t') != std::string::npos) {
    // libyaml rejects tabs in indentation; report where, even if it is inside a value.
    int line = 1;
    for (char c : text) {
      if (c == '\t') break;
      line += c == '\n';
    }
    warn("", "contains a tab character; YAML forbids tabs for indentation", line);
  }
  YamlNode root;
  ParseFailure failure;
  if (!BuildTree(text, &root, &failure)) {
    error("", failure.message, failure.line);
    return rep;
  }
  Problems located;
  const FlatDoc doc = Flatten(root, Layout::kRos2, options.node_key, &located);
  for (const auto& p : located.items()) error(p.path, p.message, 0);
  if (!located.empty() && doc.entries.empty()) return rep;

  std::map<std::string, const DeclaredParam*> table;
  for (const auto& d : declared) table[d.key] = &d;
  std::map<std::string, std::vector<const YamlNode*>> seen;
  for (const auto& e : doc.entries) seen[e.key].push_back(e.node);

  for (const auto& [key, nodes] : seen) {
    if (nodes.size() > 1)
      warn(key,
           "given " + std::to_string(nodes.size()) + " times; the ROS 2 parser keeps the last (" +
               Render(*nodes.back()) + ")",
           nodes.back()->line);
    for (const YamlNode* n : nodes) {
      if (n->kind == YamlNode::Kind::kNull) {
        error(key, "no value: the ROS 2 parser rejects an empty value", n->line);
        continue;
      }
      std::string problem;
      const ParamType lit = LiteralType(*n, &problem);
      if (n->kind == YamlNode::Kind::kSequence && !problem.empty() &&
          problem.rfind("array of ", 0) != 0) {
        error(key, problem, n->line);
        continue;
      }
      auto it = table.find(key);
      if (it == table.end()) {
        warn(key, "not declared by the node: it is silently ignored there (typo?)", n->line);
        continue;
      }
      const DeclaredParam& d = *it->second;
      if (d.workspace_only)
        warn(key, "a workspace key the car's node does not declare: ignored there", n->line);
      if (lit != d.type) {
        std::string msg =
            std::string("declared as ") + ParamTypeName(d.type) + " but written " +
            (problem.empty() ? std::string("as ") + ParamTypeName(lit) + " " + Render(*n)
                             : problem) +
            ": the node would throw InvalidParameterTypeException at start-up";
        if (d.type == ParamType::kDouble && lit == ParamType::kInt)
          msg += " (write " + n->text + ".0)";
        error(key, msg, n->line);
        continue;
      }
      if (lit == ParamType::kDouble) {
        double x = 0;
        ParseDouble(n->text, &x);
        if (!std::isfinite(x)) error(key, "value " + n->text + " is not finite", n->line);
      } else if (lit == ParamType::kDoubleArray) {
        for (const auto& item : n->items) {
          double x = 0;
          ParseDouble(item.text, &x);
          if (!std::isfinite(x)) error(key, "element " + item.text + " is not finite", item.line);
        }
      }
    }
  }
  if (options.expect_complete)
    for (const auto& d : declared)
      if (!d.optional && !seen.count(d.key))
        warn(d.key, "not set: the node keeps its code default", 0);
  return rep;
}

}  // namespace scw::params
