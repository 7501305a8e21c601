#include "params/io/write.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>

namespace scw::params {

std::string FormatDouble(double x) {
  if (std::isnan(x)) return ".nan";
  if (std::isinf(x)) return x > 0 ? ".inf" : "-.inf";
  char buf[64];
  auto res = std::to_chars(buf, buf + sizeof(buf), x);
  std::string s(buf, res.ptr);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

std::string FormatDoubleList(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (i) s += ", ";
    s += FormatDouble(v[i]);
  }
  return s + "]";
}

std::string QuoteString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\r':
        out += "\\r";
        break;
      default:
        // Other control characters would not survive a YAML reader (raw ones are refused or
        // folded): escape them.
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
          char buf[8];
          std::snprintf(buf, sizeof(buf), "\\x%02x", static_cast<unsigned>(c & 0xff));
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string FlowScalar(const std::string& s) {
  bool plain = !s.empty() && (std::isalnum(static_cast<unsigned char>(s[0])) || s[0] == '_');
  for (unsigned char c : s)
    plain = plain && (std::isalnum(c) || c == '_' || c == '.' || c == '-' || c == '+' || c == '=' ||
                      c == '/');
  plain = plain && s != "null" && s != "Null" && s != "NULL";  // YAML reads those as null
  return plain ? s : QuoteString(s);
}

namespace {

struct Tree {
  std::string name;
  std::string value;  // leaf when non-empty (or a list)
  std::string comment;
  std::vector<Tree> children;
  const std::vector<std::string>* items = nullptr;  // a list of flow maps

  Tree& Child(const std::string& n) {
    for (auto& c : children)
      if (c.name == n && c.value.empty() && !c.items) return c;
    children.push_back(Tree{n, "", "", {}});
    return children.back();
  }
};

void Emit(const Tree& t, int indent, std::string* out) {
  for (const auto& c : t.children) {
    out->append(static_cast<std::size_t>(indent), ' ');
    *out += c.name;
    *out += ':';
    if (c.items && c.items->empty()) {
      *out += " []\n";
    } else if (c.items) {
      *out += '\n';
      for (const auto& item : *c.items) {
        out->append(static_cast<std::size_t>(indent + 2), ' ');
        *out += "- " + item + "\n";
      }
    } else if (!c.value.empty()) {
      *out += ' ';
      *out += c.value;
      if (!c.comment.empty()) *out += "  # " + c.comment;
      *out += '\n';
    } else {
      *out += '\n';
      Emit(c, indent + 2, out);
    }
  }
}

}  // namespace

std::string EmitNested(const std::vector<EmitEntry>& entries, const std::string& node_key,
                       const std::string& header) {
  Tree root;
  for (const auto& e : entries) {
    Tree* t = &root;
    std::size_t start = 0;
    while (true) {
      const std::size_t dot = e.key.find('.', start);
      if (dot == std::string::npos) {
        t->children.push_back(
            Tree{e.key.substr(start), e.value, e.comment, {}, e.list ? &e.items : nullptr});
        break;
      }
      t = &t->Child(e.key.substr(start, dot - start));
      start = dot + 1;
    }
  }
  std::string out;
  if (!header.empty()) {
    std::size_t start = 0;
    while (start <= header.size()) {
      std::size_t nl = header.find('\n', start);
      if (nl == std::string::npos) nl = header.size();
      out += "# " + header.substr(start, nl - start) + "\n";
      start = nl + 1;
    }
  }
  if (node_key.empty()) {
    if (entries.empty()) return out + "{}\n";
    Emit(root, 0, &out);
  } else {
    out += node_key + ":\n  ros__parameters:";
    if (entries.empty()) {
      out += " {}\n";  // an overrides file with nothing to override
    } else {
      out += "\n";
      Emit(root, 4, &out);
    }
  }
  return out;
}

}  // namespace scw::params
