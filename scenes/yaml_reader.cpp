// The YAML scene reader's text helpers, field readers and document parsing (yaml_reader.hpp).
#include "scenes/yaml_reader.hpp"

#include <yaml-cpp/depthguard.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <system_error>

#include "engine/number_text.hpp"
#include "scenes/scene_files.hpp"

namespace tumble::scene_yaml {

// Text helpers.

std::string join(Keys keys) {
  std::string s;
  for (std::string_view k : keys) {
    if (!s.empty()) {
      s += ", ";
    }
    s += k;
  }
  return s;
}

bool contains(Keys keys, std::string_view key) {
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}

std::string index(const std::string& path, std::size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

// Shortest text that reads back to the same double.
std::string fmt(Real v) {
  return number_text(v);
}

// The path of a field in a map. Keys come from the file and may hold anything, so they are made
// printable: a field path must never break the one-line message.
std::string child(const std::string& path, std::string_view key) {
  const std::string k = printable(key);
  return path.empty() ? k : path + "." + k;
}

// What a node holds, for the "got ..." end of a message.
std::string describe(const Node& n) {
  switch (n.kind) {
    case Node::Kind::null:
      return "nothing (an empty value)";
    case Node::Kind::sequence:
      return n.size() == 0
                 ? std::string("an empty list")
                 : "a list of " + std::to_string(n.size()) + (n.size() == 1 ? " item" : " items");
    case Node::Kind::map:
      return n.size() == 0 ? "an empty map" : "a map";
    case Node::Kind::scalar:
      // Say so when it was quoted: a quoted number is a string.
      if (n.style == Node::Style::quoted) {
        return "the quoted string \"" + printable(n.scalar) + "\"";
      }
      return printable(n.scalar);
  }
  return "an undefined value";
}

// Edit distance for "did you mean" hints; field names are short, so O(n m) is nothing.
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) {
    row[j] = j;
  }
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

// Strict YAML 1.2 core-schema decimal: [-+]? (.[0-9]+ | [0-9]+(.[0-9]*)?) ([eE][-+]?[0-9]+)?
// yaml-cpp's own conversion goes through a stringstream and accepts more than this (and quietly
// maps .nan and .inf), so numbers are parsed here. Hex, octal and '_' separators are rejected.
NumberStatus parse_number(const std::string& s, Real& out) {
  std::size_t j = 0;
  // Advances j over a run of digits and says how many there were.
  const auto skip_digits = [&] {
    const std::size_t start = j;
    while (j < s.size() && s[j] >= '0' && s[j] <= '9') {
      ++j;
    }
    return j - start;
  };
  if (!s.empty() && (s[0] == '+' || s[0] == '-')) {
    j = 1;
  }
  std::string rest = s.substr(j);
  std::transform(rest.begin(), rest.end(), rest.begin(), [](char c) {
    return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c;
  });
  if (rest == ".inf" || rest == "inf" || rest == "infinity" || rest == ".nan" || rest == "nan") {
    return NumberStatus::not_finite;
  }
  std::size_t mantissa_digits = skip_digits();
  if (j < s.size() && s[j] == '.') {
    ++j;
    mantissa_digits += skip_digits();
  }
  if (mantissa_digits == 0) {
    return NumberStatus::not_a_number;
  }
  if (j < s.size() && (s[j] == 'e' || s[j] == 'E')) {
    ++j;
    if (j < s.size() && (s[j] == '+' || s[j] == '-')) {
      ++j;
    }
    if (skip_digits() == 0) {
      return NumberStatus::not_a_number;
    }
  }
  if (j != s.size()) {
    return NumberStatus::not_a_number;
  }
  // from_chars is locale-independent but takes no leading '+'.
  const char* first = s.data() + (s[0] == '+' ? 1 : 0);
  const char* last = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(first, last, out);
  if (ec == std::errc::result_out_of_range) {
    return NumberStatus::out_of_range;
  }
  if (ec != std::errc() || ptr != last) {
    return NumberStatus::not_a_number;
  }
  if (!std::isfinite(out)) {
    return NumberStatus::not_finite;
  }
  return NumberStatus::ok;
}

YAML::Mark mark_or(const Node& n, const YAML::Mark& fallback) {
  if (n.is_null() || n.mark.line < 0) {
    return fallback;
  }
  return n.mark;
}

Fields Loader::read_map(const Node& node, const YAML::Mark& mark, const std::string& path,
                        std::string_view what, bool null_is_empty) const {
  Fields fields;
  fields.path = path;
  fields.mark = mark_or(node, mark);
  if (node.is_null() && null_is_empty) {
    return fields;
  }
  if (!node.is_map()) {
    fail(mark, path, "expected " + std::string(what) + ", got " + describe(node));
  }
  fields.entries.reserve(node.size());
  // Index of each key seen so far: a generated file may hold very many materials.
  std::unordered_map<std::string, std::size_t> seen;
  for (std::size_t i = 0; i + 1 < node.items.size(); i += 2) {
    const Node& key = *node.items[i];
    const Node& value = *node.items[i + 1];
    const YAML::Mark key_mark = mark_or(key, fields.mark);
    if (!key.is_scalar()) {
      fail(key_mark, path, "expected a field name, got " + describe(key) + " as a key");
    }
    const std::string& name = key.scalar;
    const auto [first, inserted] = seen.try_emplace(name, fields.entries.size());
    if (!inserted) {
      fail(key_mark, child(path, name),
           "duplicate field '" + printable(name) + "' (first given on line " +
               std::to_string(fields.entries[first->second].key_mark.line + 1) + ")");
    }
    fields.entries.push_back({name, key_mark, value});
  }
  return fields;
}

void Loader::check_known(const Fields& fields, Keys allowed) const {
  for (const Entry& e : fields.entries) {
    if (contains(allowed, e.key)) {
      continue;
    }
    const std::string where = fields.path.empty() ? "at the top level" : "in " + fields.path;
    std::string reason =
        "unknown field '" + printable(e.key) + "' " + where + "; expected one of: " + join(allowed);
    if (e.key == "<<") {
      reason += " (YAML merge keys '<<' are not supported; write the fields out)";
    } else {
      // A near miss is almost always a typo of a real field.
      std::string_view best;
      std::size_t best_distance = 3;
      for (std::string_view k : allowed) {
        const std::size_t d = edit_distance(e.key, k);
        if (d < best_distance) {
          best_distance = d;
          best = k;
        }
      }
      if (!best.empty()) {
        reason += " (did you mean '" + std::string(best) + "'?)";
      }
    }
    fail(e.key_mark, child(fields.path, e.key), reason);
  }
}

Real Loader::read_real(const Node& n, const YAML::Mark& mark, const std::string& path,
                       const RealSpec& spec) const {
  // Built only on failure: a scene can hold millions of numbers.
  const auto reject = [&](std::string_view why) {
    std::string reason = "expected " + std::string(spec.what);
    if (!spec.range.empty()) {
      reason += " (" + std::string(spec.range) + ")";
    }
    fail(mark, path, reason + ", got " + describe(n) + std::string(why));
  };
  // Quoted or !!str-tagged scalars are strings even when they look like numbers.
  if (!n.is_scalar() || n.is_string()) {
    reject("");
  }
  Real v = 0;
  switch (parse_number(n.scalar, v)) {
    case NumberStatus::ok:
      break;
    case NumberStatus::not_a_number:
      reject("");
      break;
    case NumberStatus::not_finite:
      reject(", which is not a finite number");
      break;
    case NumberStatus::out_of_range:
      reject(", which is too large or too small for a double");
      break;
  }
  if (v < spec.lo || v > spec.hi || (spec.lo_open && v == spec.lo)) {
    reject("");
  }
  return v;
}

std::int64_t Loader::read_int(const Entry& e, const std::string& path, const IntSpec& spec) const {
  // Parsed as a real first so that 1e6 is accepted as the integer it is; 2.5 is not.
  const Real v = read_real(e, path, RealSpec{spec.what, spec.range, -kInf, kInf});
  const auto reject = [&](std::string_view why) {
    fail(e.mark(), path,
         "expected " + std::string(spec.what) + " (" + std::string(spec.range) + "), got " +
             describe(e.value) + std::string(why));
  };
  if (std::floor(v) != v) {
    reject(", which is not an integer");
  }
  // Compared as reals before the cast, so an absurd count never overflows the conversion.
  if (v < static_cast<Real>(spec.lo) || v > static_cast<Real>(spec.hi)) {
    reject("");
  }
  return static_cast<std::int64_t>(v);
}

bool Loader::read_bool(const Entry& e, const std::string& path) const {
  // Only the YAML 1.2 core spellings: 'yes', 'on' and 'y' are YAML 1.1 booleans that yaml-cpp
  // would accept, and 'n' for 'no' (the Norway problem) is exactly the surprise to avoid.
  const Node& n = e.value;
  if (n.is_scalar() && !n.is_string()) {
    const std::string& s = n.scalar;
    if (s == "true" || s == "True" || s == "TRUE") {
      return true;
    }
    if (s == "false" || s == "False" || s == "FALSE") {
      return false;
    }
  }
  fail(e.mark(), path, "expected true or false, got " + describe(n));
}

std::string Loader::read_word(const Entry& e, const std::string& path,
                              std::string_view what) const {
  if (!e.value.is_scalar() || e.value.scalar.empty()) {
    fail(e.mark(), path, "expected " + std::string(what) + ", got " + describe(e.value));
  }
  return e.value.scalar;
}

std::string Loader::read_name(const Entry& e, const std::string& path,
                              std::string_view what) const {
  const std::string name = read_word(e, path, what);
  // Body names go unquoted into the trajectory CSV and into one-line messages.
  const bool clean = std::none_of(name.begin(), name.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u < 0x20 || u == 0x7f || c == ',' || c == '"';
  });
  if (!clean || name.size() > kMaxNameLength) {
    fail(e.mark(), path,
         "expected " + std::string(what) +
             " of at most 256 bytes without commas, double quotes or control characters "
             "(names are written unquoted to CSV), got " +
             describe(e.value));
  }
  return name;
}

// Parses the text into `doc` and returns the root of its one document. yaml-cpp 0.7 can get
// stuck on some malformed input such as a lone ',' (jbeder/yaml-cpp#1040, fixed upstream after
// 0.8 by PR #1319): it reports an empty document without consuming the offending token, again
// and again, and LoadAll allocates until the process is killed. So documents are read here, at
// most three, and one that starts where the previous one did means the parser is stuck.
SceneError yaml_syntax_error(const YAML::Exception& e, const std::string& source) {
  const int line = e.mark.line >= 0 ? e.mark.line + 1 : 0;
  const int column = e.mark.line >= 0 ? e.mark.column + 1 : 0;
  if (const auto* deep = dynamic_cast<const YAML::DeepRecursion*>(&e))
    return SceneError(source, line, column, "",
                      "YAML nested deeper than " + std::to_string(deep->depth()) +
                          " levels (lists or maps inside each other); a scene needs a few");
  return SceneError(source, line, column, "", "YAML syntax error: " + e.msg);
}

const Node& Loader::parse(std::string_view text, DocumentBuilder& doc,
                          std::string_view required) const {
  std::istringstream in{std::string(text)};
  YAML::Parser parser(in);
  // A third document is read only to tell a stuck parser from a genuine second document.
  while (doc.starts.size() < 3 && parser.HandleNextDocument(doc)) {
  }
  for (std::size_t i = 1; i < doc.starts.size(); ++i) {
    const YAML::Mark& mark = doc.starts[i];
    if (mark.pos == doc.starts[i - 1].pos) {
      const auto at = static_cast<std::size_t>(mark.pos);
      const std::string token = at < text.size() ? printable(text.substr(at, 1)) : "end of input";
      fail(mark, "", "YAML syntax error: unexpected '" + token + "'");
    }
  }
  if (doc.starts.size() > 1) {
    fail(doc.starts[1], "",
         "the file holds more than one YAML document ('---'); a scene file holds exactly one");
  }
  if (doc.roots.empty() || doc.roots[0]->is_null()) {
    fail(YAML::Mark(), std::string(required),
         "missing required field '" + std::string(required) +
             "' (the file holds no YAML document, or an empty one)");
  }
  return *doc.roots[0];
}

std::string read_file(const std::filesystem::path& path, const std::string& source) {
  std::string why;
  if (std::optional<std::string> text = regular_file_text(path, why))
    return std::move(*text);
  throw SceneError(source, 0, 0, "", "cannot open scene file (" + why + ")");
}

}  // namespace tumble::scene_yaml
