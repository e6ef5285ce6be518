#include "scene/json_reader.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "core/errors.hpp"
#include "scene/key_suggest.hpp"

namespace varsph::scene {

namespace {

// Deepest nesting of arrays/objects in a JSON text (strings skipped). Scenes nest a few levels; a
// hostile file nested 10^5 deep would overflow the stack of every recursive walk over the tree.
int nesting_depth(const std::string& text) {
  int depth = 0, deepest = 0;
  bool in_string = false, escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return deepest;
}
constexpr int kMaxDepth = 64;

}  // namespace

json::json_pointer pointer_of(const std::string& dotted) {
  std::string p;
  std::stringstream ss(dotted);
  std::string part;
  while (std::getline(ss, part, '.')) p += "/" + part;
  return json::json_pointer(p);
}

JsonReader::JsonReader(json root, std::string file) : root_(std::move(root)), file_(std::move(file)) {
  if (!root_.is_object()) throw InputError(file_ + ": expected a JSON object at the top level");
}

const json* JsonReader::raw(const std::string& path) const {
  const auto ptr = pointer_of(path);
  if (!root_.contains(ptr)) return nullptr;
  return &root_.at(ptr);
}

bool JsonReader::has(const std::string& path) const {
  const json* v = raw(path);
  return v && !v->is_null();
}

void JsonReader::record(const std::string& path, const json& value) {
  known_.insert(path);
  resolved_[pointer_of(path)] = value;
}

namespace {
// The blocks of a scene (docs/scene.md): candidates for a misspelt top-level key even when the scene names
// none of the keys of a block (the parse then never meets them).
const std::vector<std::string> kTopLevel = {"name", "setup", "dimension", "domain", "particles", "kernel", "gravity",
                                            "fluid", "bodies", "physics", "boundary", "integrator", "time",
                                            "output", "checkpoint", "probes", "log", "health", "execution",
                                            "parallel", "moorings", "contact"};

std::vector<std::string> split_dots(const std::string& path) {
  std::vector<std::string> parts;
  std::stringstream ss(path);
  std::string part;
  while (std::getline(ss, part, '.')) parts.push_back(part);
  return parts;
}

bool at_or_under(const std::string& path, const std::string& key) {
  return path == key || path.rfind(key + ".", 0) == 0;
}
}  // namespace

void JsonReader::note_overrides(const std::vector<std::string>& assignments) {
  for (const auto& a : assignments) overrides_.emplace_back(a.substr(0, a.find('=')), a);
}

std::string JsonReader::origin(const std::string& path) const {
  for (auto it = overrides_.rbegin(); it != overrides_.rend(); ++it)  // the last --set of a key wins
    if (at_or_under(path, it->first) || at_or_under(it->first, path))
      return "--set '" + it->second + "' (scene " + file_ + ")";
  return file_;
}

void JsonReader::supply(const std::string& path, const json& value, const std::string& setup) {
  root_[pointer_of(path)] = value;
  supplied_.push_back(path);
  setup_ = setup;
}

std::string JsonReader::supplied_note(const std::string& path) const {
  for (const auto& k : supplied_)
    if (at_or_under(path, k))
      return " (not in the scene: the default of \"setup\": \"" + setup_ + "\"; name the key in the scene, or set "
             "\"setup\": \"paper\" for the paper's defaults, docs/scene.md \"Set-up\")";
  return "";
}

void JsonReader::fail(const std::string& path, const std::string& expected) const {
  if (expected.find("required key is missing") != std::string::npos) throw_if_misspelt(path);
  throw InputError(origin(path) + ": key '" + path + "'" + supplied_note(path) + ": expected " + expected);
}
void JsonReader::fail_got(const std::string& path, const std::string& expected, const json& got) const {
  throw InputError(origin(path) + ": key '" + path + "'" + supplied_note(path) + ": expected " + expected + ", got " +
                   got.dump(-1, ' ', false, json::error_handler_t::replace));
}

bool JsonReader::is_schema_prefix(const std::string& path) const {
  if (path.find('.') == std::string::npos &&
      std::find(kTopLevel.begin(), kTopLevel.end(), path) != kTopLevel.end())
    return true;
  for (const auto& k : known_)  // a key read, or a path above one (a known leaf such as the array
    if (at_or_under(k, path)) return true;  // `bodies` says nothing about what is under it)
  for (const auto& k : known_subtrees_)  // a subtree taken whole: everything in it is known
    if (at_or_under(k, path) || at_or_under(path, k)) return true;
  return false;
}

std::vector<std::string> JsonReader::children_of(const std::string& parent) const {
  std::set<std::string> out;
  if (parent.empty()) out.insert(kTopLevel.begin(), kTopLevel.end());
  if (const auto it = expected_.find(parent); it != expected_.end()) out.insert(it->second.begin(), it->second.end());
  const std::string pre = parent.empty() ? "" : parent + ".";
  for (const auto* set : {&known_, &known_subtrees_})
    for (const auto& k : *set)
      if (k.rfind(pre, 0) == 0 && k.size() > pre.size()) out.insert(split_dots(k.substr(pre.size()))[0]);
  return {out.begin(), out.end()};
}

std::string JsonReader::unknown_message(const std::string& leaf) const {
  const auto parts = split_dots(leaf);
  std::string parent, path;
  for (const auto& p : parts) {
    path = parent.empty() ? p : parent + "." + p;
    if (!is_schema_prefix(path)) break;
    parent = path;
  }
  const auto guess = closest_key(parts[split_dots(path).size() - 1], children_of(parent));
  return origin(leaf) + ": unknown key '" + path + "'" +
         (guess ? " (did you mean '" + (parent.empty() ? *guess : parent + "." + *guess) + "'?)" : "") +
         (path != leaf ? " in '" + leaf + "'" : "") + "; not part of the scene schema, see docs/scene.md";
}

void JsonReader::throw_if_misspelt(const std::string& path) const {
  const auto parts = split_dots(path);
  std::string parent;
  for (const auto& p : parts) {
    const std::string here = parent.empty() ? p : parent + "." + p;
    if (!raw(here)) {  // the first part of the path the scene lacks: a typo of it beside it?
      const json* obj = parent.empty() ? &root_ : raw(parent);
      if (!obj || !obj->is_object()) return;
      for (auto it = obj->begin(); it != obj->end(); ++it) {
        const std::string sibling = parent.empty() ? it.key() : parent + "." + it.key();
        if (is_schema_prefix(sibling) || it.value().is_null()) continue;
        if (closest_key(it.key(), {p}))
          throw InputError(origin(sibling) + ": unknown key '" + sibling + "' (did you mean '" + here + "'? '" +
                           path + "' is required); not part of the scene schema, see docs/scene.md");
      }
      return;
    }
    parent = here;
  }
}

double JsonReader::number(const std::string& path, std::optional<double> def, double lo, double hi,
                          const std::string& what) {
  const json* v = raw(path);
  double x;
  if (!v || v->is_null()) {
    if (!def) fail(path, what + " (required key is missing)");
    x = *def;
  } else {
    if (!v->is_number()) fail_got(path, what, *v);
    x = v->get<double>();
    if (!(x >= lo && x <= hi))
      fail_got(path, what + " in [" + json(lo).dump() + ", " + json(hi).dump() + "]", *v);
  }
  record(path, x);
  return x;
}

double JsonReader::positive(const std::string& path, std::optional<double> def, const std::string& what) {
  const json* v = raw(path);
  if (v && v->is_number() && !(v->get<double>() > 0)) fail_got(path, "a positive " + what, *v);
  return number(path, def, 0, 1e300, "a positive " + what);
}

long JsonReader::integer(const std::string& path, std::optional<long> def, long lo, long hi) {
  const json* v = raw(path);
  long x;
  if (!v || v->is_null()) {
    if (!def) fail(path, "an integer (required key is missing)");
    x = *def;
  } else {
    if (!v->is_number_integer()) fail_got(path, "an integer", *v);
    x = v->get<long>();
    if (x < lo || x > hi)
      fail_got(path, "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]", *v);
  }
  record(path, x);
  return x;
}

bool JsonReader::boolean(const std::string& path, std::optional<bool> def) {
  const json* v = raw(path);
  bool x;
  if (!v || v->is_null()) {
    if (!def) fail(path, "true or false (required key is missing)");
    x = *def;
  } else {
    if (!v->is_boolean()) fail_got(path, "true or false", *v);
    x = v->get<bool>();
  }
  record(path, x);
  return x;
}

std::string JsonReader::text(const std::string& path, std::optional<std::string> def) {
  const json* v = raw(path);
  std::string x;
  if (!v || v->is_null()) {
    if (!def) fail(path, "a string (required key is missing)");
    x = *def;
  } else {
    if (!v->is_string()) fail_got(path, "a string", *v);
    x = v->get<std::string>();
  }
  record(path, x);
  return x;
}

std::string JsonReader::choice(const std::string& path, std::optional<std::string> def,
                               const std::vector<std::string>& allowed) {
  std::string list;
  for (auto& a : allowed) list += (list.empty() ? "" : " | ") + ("\"" + a + "\"");
  const json* v = raw(path);
  if (v && !v->is_null() && !v->is_string()) fail_got(path, "one of " + list, *v);
  const std::string x = text(path, def);
  for (auto& a : allowed)
    if (a == x) return x;
  fail_got(path, "one of " + list, json(x));
}

// Reads an optional array of T (exactly `size` elements unless size == 0): one place for the
// missing / wrong-shape / wrong-element-type errors of vector(), bools() and strings().
template <class T, class IsT>
std::vector<T> JsonReader::array_of(const std::string& path, std::size_t size, std::optional<std::vector<T>> def,
                                    const std::string& expected, IsT is_t) {
  const json* v = raw(path);
  std::vector<T> x;
  if (!v || v->is_null()) {
    if (!def) fail(path, expected + " (required key is missing)");
    x = *def;
  } else {
    if (!v->is_array() || (size > 0 && v->size() != size)) fail_got(path, expected, *v);
    for (auto& e : *v) {
      if (!is_t(e)) fail_got(path, expected, *v);
      x.push_back(e.template get<T>());
    }
  }
  record(path, x);
  return x;
}

std::vector<double> JsonReader::vector(const std::string& path, std::size_t size,
                                       std::optional<std::vector<double>> def, const std::string& what) {
  return array_of<double>(path, size, std::move(def),
                          "an array of " + std::to_string(size) + " numbers (" + what + ")",
                          [](const json& e) { return e.is_number(); });
}

std::vector<bool> JsonReader::bools(const std::string& path, std::size_t size,
                                    std::optional<std::vector<bool>> def) {
  return array_of<bool>(path, size, std::move(def), "an array of " + std::to_string(size) + " booleans",
                        [](const json& e) { return e.is_boolean(); });
}

std::vector<std::string> JsonReader::strings(const std::string& path,
                                             std::optional<std::vector<std::string>> def) {
  return array_of<std::string>(path, 0, std::move(def), "an array of strings",
                               [](const json& e) { return e.is_string(); });
}

std::size_t JsonReader::array_size(const std::string& path) {
  const json* v = raw(path);
  if (!v || v->is_null()) return 0;
  if (!v->is_array()) fail_got(path, "an array", *v);
  known_.insert(path);
  return v->size();
}

json JsonReader::subtree(const std::string& path, const json& def) {
  const json* v = raw(path);
  json x = (v && !v->is_null()) ? *v : def;
  known_subtrees_.insert(path);
  resolved_[pointer_of(path)] = x;
  return x;
}

namespace {
void walk(const json& node, const std::string& path, std::vector<std::string>& out) {
  if (node.is_object()) {
    if (node.empty() && !path.empty()) out.push_back(path);
    for (auto it = node.begin(); it != node.end(); ++it)
      walk(it.value(), path.empty() ? it.key() : path + "." + it.key(), out);
  } else if (node.is_array() && !node.empty() && (node[0].is_object())) {
    for (std::size_t i = 0; i < node.size(); ++i) walk(node[i], path + "." + std::to_string(i), out);
  } else if (!node.is_null()) {  // null is the same as absent (`--set physics.xsph=null` removes a term)
    out.push_back(path);
  }
}
}  // namespace

void JsonReader::check_unknown() const {
  std::vector<std::string> leaves;
  walk(root_, "", leaves);
  for (const auto& leaf : leaves) {
    if (leaf.empty() || known_.count(leaf)) continue;
    bool under = false;
    for (const auto& s : known_subtrees_)
      if (leaf == s || leaf.rfind(s + ".", 0) == 0) under = true;
    // "comment" keys are allowed anywhere for documentation
    const auto last = leaf.substr(leaf.rfind('.') == std::string::npos ? 0 : leaf.rfind('.') + 1);
    if (under || last == "comment" || last.rfind("_comment", 0) == 0 || last == "description") continue;
    throw InputError(unknown_message(leaf));
  }
}

json read_json_file(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file.string() + ": cannot open scene file (does it exist and is it readable?)");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  if (nesting_depth(text) > kMaxDepth)
    throw InputError(file.string() + ": JSON nested deeper than " + std::to_string(kMaxDepth) +
                     " levels; expected a scene (a few levels of objects and arrays)");
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    // translate the byte offset into line:column
    std::size_t line = 1, col = 1;
    const std::size_t upto = std::min<std::size_t>(e.byte ? e.byte - 1 : 0, text.size());
    for (std::size_t k = 0; k < upto; ++k) {
      if (text[k] == '\n') { ++line; col = 1; } else { ++col; }
    }
    std::string msg = e.what();
    const auto pos = msg.find("syntax error");
    throw InputError(file.string() + ":" + std::to_string(line) + ":" + std::to_string(col) +
                     ": JSON " + (pos != std::string::npos ? msg.substr(pos) : msg));
  } catch (const json::exception& e) {  // e.g. out_of_range: "number overflow parsing '1e400'"
    throw InputError(file.string() + ": JSON " + e.what() + "; expected numbers within +-1.8e308");
  }
}

void apply_override(json& root, const std::string& assignment, const std::string& file) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set '" + assignment + "': expected KEY=VALUE (e.g. integrator.alpha=0.5)");
  const std::string key = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  if (nesting_depth(text) > kMaxDepth)
    throw InputError("--set '" + key + "': VALUE nested deeper than " + std::to_string(kMaxDepth) + " levels");
  json value;
  try {
    value = json::parse(text);
  } catch (const json::exception&) {
    value = text;  // not valid JSON (or a number out of range): taken as a string
    try {
      (void)value.dump();  // every later dump (messages, run.json, checkpoints) needs valid UTF-8
    } catch (const json::exception&) {
      throw InputError("--set " + key + " (scene " + file + "): VALUE is neither JSON nor valid UTF-8 text");
    }
  }
  json* node = &root;
  std::stringstream ss(key);
  std::string part;
  std::vector<std::string> parts;
  while (std::getline(ss, part, '.')) parts.push_back(part);
  if (parts.size() > std::size_t(kMaxDepth))
    throw InputError("--set " + key.substr(0, 80) + "... (scene " + file + "): more than " +
                     std::to_string(kMaxDepth) + " levels of keys");
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const std::string& p = parts[k];
    const bool last = k + 1 == parts.size();
    if (node->is_array()) {
      char* end = nullptr;
      const long idx = std::strtol(p.c_str(), &end, 10);
      if (*end != '\0' || idx < 0 || std::size_t(idx) >= node->size())
        throw InputError("--set '" + assignment + "' (scene " + file + "): index '" + p +
                         "' is out of range (the array has " + std::to_string(node->size()) + " elements)");
      node = &(*node)[std::size_t(idx)];
    } else {
      if (node->is_null()) *node = json::object();
      if (!node->is_object())
        throw InputError("--set '" + assignment + "' (scene " + file + "): '" + p +
                         "' is below a value that is not an object");
      node = &(*node)[p];
    }
    if (last) *node = value;
  }
}

}  // namespace varsph::scene
