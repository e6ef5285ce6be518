#pragma once
// Validated access to a scene's JSON. Each accessor names its key path, default, range and unit; it
// records the key as known and writes the value it used into `resolved()`, so the resolved scene
// (run.json, checkpoints, `varsph info`) lists every parameter with its default. After parsing,
// check_unknown() rejects keys nobody asked for. Errors are InputError naming the file and key.
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace varsph::scene {

using nlohmann::json;

class JsonReader {
 public:
  JsonReader(json root, std::string file);

  bool has(const std::string& path) const;
  double number(const std::string& path, std::optional<double> def, double lo, double hi,
                const std::string& what);
  // strictly positive number
  double positive(const std::string& path, std::optional<double> def, const std::string& what);
  long integer(const std::string& path, std::optional<long> def, long lo, long hi);
  bool boolean(const std::string& path, std::optional<bool> def);
  std::string choice(const std::string& path, std::optional<std::string> def,
                     const std::vector<std::string>& allowed);
  std::string text(const std::string& path, std::optional<std::string> def);
  std::vector<double> vector(const std::string& path, std::size_t size,
                             std::optional<std::vector<double>> def, const std::string& what);
  std::vector<bool> bools(const std::string& path, std::size_t size, std::optional<std::vector<bool>> def);
  std::vector<std::string> strings(const std::string& path, std::optional<std::vector<std::string>> def);
  std::size_t array_size(const std::string& path);  // 0 when absent; error when not an array
  // Accepts a whole subtree as-is (validated by its own module) and returns it.
  json subtree(const std::string& path, const json& def);
  const json* raw(const std::string& path) const;
  // Marks a key as known without reading it (an object whose presence switches a term on).
  void mark_known(const std::string& path) { known_.insert(path); }
  // The --set KEY=VALUE arguments applied to the tree: an error about KEY (or a key under it) names the
  // argument, not only the file (issue 35).
  void note_overrides(const std::vector<std::string>& assignments);
  // Valid keys under `parent` that the parse may not meet (optional blocks, mesh keys): candidates of
  // "did you mean" only; they do not make a key known.
  void expect_keys(const std::string& parent, const std::vector<std::string>& names) {
    expected_[parent].insert(names.begin(), names.end());
  }
  // "FILE" or "--set 'KEY=VALUE' (scene FILE)": where the value at `path` came from.
  std::string origin(const std::string& path) const;
  // Puts `value` at `path`, a key the scene leaves out, as the default of the set-up `setup` (top-level
  // `setup`, issue 35; scene/parse_scene.cpp). An error about the key then says that the set-up gave it.
  void supply(const std::string& path, const json& value, const std::string& setup);
  const std::vector<std::string>& supplied() const { return supplied_; }

  void check_unknown() const;
  [[noreturn]] void fail(const std::string& path, const std::string& expected) const;
  [[noreturn]] void fail_got(const std::string& path, const std::string& expected, const json& got) const;
  const json& resolved() const { return resolved_; }
  const std::string& file() const { return file_; }

 private:
  void record(const std::string& path, const json& value);
  template <class T, class IsT>
  std::vector<T> array_of(const std::string& path, std::size_t size, std::optional<std::vector<T>> def,
                          const std::string& expected, IsT is_t);
  json root_;
  json resolved_ = json::object();
  std::string file_;
  // valid keys directly under `parent` ("" = top level) that the parse has met so far
  std::vector<std::string> children_of(const std::string& parent) const;
  bool is_schema_prefix(const std::string& path) const;
  // the message for a key nobody asked for: the first unknown component of `leaf` and the closest valid key
  std::string unknown_message(const std::string& leaf) const;
  // a required key `path` is missing: an unknown key beside where it should be that is a typo of it
  void throw_if_misspelt(const std::string& path) const;
  std::set<std::string> known_;
  std::set<std::string> known_subtrees_;
  std::vector<std::pair<std::string, std::string>> overrides_;  // (KEY, "KEY=VALUE")
  std::map<std::string, std::set<std::string>> expected_;
  std::vector<std::string> supplied_;  // keys the set-up filled in (supply())
  std::string setup_;                  // the set-up that filled them
  // " (not in the scene: ...)" when `path` is (under) a key the set-up supplied, else ""
  std::string supplied_note(const std::string& path) const;
};

// "a.b.0.c" -> JSON pointer "/a/b/0/c"
json::json_pointer pointer_of(const std::string& dotted);

// Reads and parses a JSON file; a syntax error names line:column (InputError).
json read_json_file(const std::filesystem::path& file);

// Applies --set KEY=VALUE (VALUE parsed as JSON, else taken as a string). Unknown keys are caught
// later by check_unknown(); an array index out of range is an error here.
void apply_override(json& root, const std::string& assignment, const std::string& file);

}  // namespace varsph::scene
