#pragma once
// What `varsph study` was asked to do (src/app/command_study.cpp fills it; docs/study.md).
#include <filesystem>
#include <string>
#include <vector>

namespace varsph::study {

enum class Refine { Dx, Dt, Both };

struct Window {
  double t0 = 0, t1 = 0;
  std::string label() const;  // "0:0.3" (the suffix of the quantity names)
};

struct StudyOptions {
  std::vector<std::filesystem::path> scenes;  // one: refined by the study; several: the levels, coarsest first
  std::vector<std::string> overrides;         // --set KEY=VALUE for every run
  Refine refine = Refine::Both;
  int levels = 3;
  double ratio = 2.0;
  bool ratio_given = false;
  double coarsest_dx = 0;        // --dx: the coarsest level's spacing (0: the scene's)
  int threads = 0;               // passed to every level (0: the child's default)
  double budget_minutes = 0;     // 0: no budget
  std::vector<std::string> ablate;      // TERM or KEY=VALUE, one alternative each
  std::vector<std::string> tolerances;  // "5%", "0.01", "QUANTITY=VALUE", "QUANTITY=VALUE%" (QUANTITY may use *)
  std::vector<Window> windows;          // means and series norms; default the whole run
  std::string norm = "l2";
  std::filesystem::path output;         // default runs/NAME_study
  bool overwrite = false, reuse = false, quiet = false, plots = true;
  bool extra_probes = true;             // add a front probe and a force probe per boundary body when absent
  std::vector<std::string> command_line;
};

Refine parse_refine(const std::string& s);  // dx | dt | both (InputError otherwise)
const char* to_string(Refine r);
double parse_ratio(const std::string& s);   // "2", "sqrt2" or a number > 1 (InputError otherwise)
Window parse_window(const std::string& s);  // "T0:T1" with T0 < T1 (InputError otherwise)

}  // namespace varsph::study
