// `varsph paraview RUN [RUN_B] [--state NAME] [-- PARAVIEW ARGS]`: opens the ParaView GUI on a run, the varsph plugin loaded
// and one of the bundled states (paraview/states/) shown. Sets PV_PLUGIN_PATH to paraview/plugin, the run
// directories in VARSPH_RUN_DIR / VARSPH_OTHER_RUN_DIR (what the states read), and puts paraview/shim on
// PYTHONPATH, whose usercustomize.py activates the ParaView 5.11 / Python 3.11 plugin fix for this ParaView
// even where paraview/install_compat.py was not run; then replaces itself with `paraview --state=...`.
#include <unistd.h>

#include <cstdio>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "core/errors.hpp"

namespace fs = std::filesystem;

namespace varsph {
namespace {

bool has_pvd(const fs::path& p) {
  std::error_code ec;
  if (fs::is_regular_file(p, ec)) return p.extension() == ".pvd";
  if (!fs::is_directory(p, ec)) return false;
  for (const auto& e : fs::directory_iterator(p, ec))
    if (e.path().extension() == ".pvd") return true;
  return false;
}

fs::path run_directory(const std::string& arg, const char* what) {
  const fs::path p = fs::absolute(arg).lexically_normal();
  if (!has_pvd(p))
    throw InputError(arg + ": " + what + " is not a run directory (no .pvd time series in it; expected the -o "
                     "directory of `varsph run`)");
  return fs::is_regular_file(p) ? p.parent_path() : p;
}

// paraview/ of this installation: $VARSPH_PARAVIEW_DIR, else <prefix>/share/varsph/paraview next to the
// installed binary, else the source tree the binary was built from.
fs::path paraview_dir(const std::string& argv0) {
  std::vector<fs::path> candidates;
  if (const char* env = std::getenv("VARSPH_PARAVIEW_DIR"); env && *env) candidates.emplace_back(env);
  std::error_code ec;
  const fs::path exe = fs::canonical("/proc/self/exe", ec);
  if (!ec) candidates.push_back(exe.parent_path().parent_path() / "share" / "varsph" / "paraview");
  (void)argv0;
  candidates.emplace_back(VARSPH_PARAVIEW_SOURCE_DIR);
  for (const auto& c : candidates)
    if (fs::is_regular_file(c / "plugin" / "varsph_filters.py", ec)) return c;
  throw InputError("cannot find the varsph ParaView files (plugin/varsph_filters.py): set VARSPH_PARAVIEW_DIR "
                   "to the paraview/ directory of varsph");
}

std::string prepend(const char* var, const std::string& dir) {
  const char* old = std::getenv(var);
  return (old && *old) ? dir + ":" + old : dir;
}

}  // namespace

int command_paraview(const CommandArgs& a) {
  const fs::path run = run_directory(a.run_a, "RUN");
  const bool two = !a.run_b.empty();
  const fs::path other = two ? run_directory(a.run_b, "RUN_B") : fs::path();
  const fs::path pv = paraview_dir(a.argv.empty() ? "" : a.argv[0]);

  std::string name = a.state.empty() ? (two ? "deviation" : "pressure") : a.state;
  fs::path state = pv / "states" / (fs::path(name).has_extension() ? name : name + ".py");
  if (!fs::is_regular_file(state)) state = fs::absolute(name);  // a state file of one's own
  if (!fs::is_regular_file(state))
    throw InputError("--state " + name + ": no such state; expected free_surface, pressure, deviation, open_flow, elevation (add .pvsm "
                     "for the XML state files) or the path of a .py / .pvsm state file");
  if (state.stem() == "deviation" && !two)
    throw InputError("--state deviation compares two runs: give RUN_B after RUN (varsph paraview RUN RUN_B)");

  const std::string exe = a.paraview_exe.empty() ? "paraview" : a.paraview_exe;
  const std::vector<std::pair<std::string, std::string>> env = {
      {"VARSPH_RUN_DIR", run.string()},
      {"VARSPH_OTHER_RUN_DIR", two ? other.string() : std::string()},
      {"VARSPH_PARAVIEW_DIR", pv.string()},
      {"PV_PLUGIN_PATH", prepend("PV_PLUGIN_PATH", (pv / "plugin").string())},
      {"PYTHONPATH", prepend("PYTHONPATH", (pv / "shim").string())},
  };
  std::vector<std::string> argv = {exe, "--state=" + state.string()};
  argv.insert(argv.end(), a.paraview_args.begin(), a.paraview_args.end());
  if (a.dry_run) {
    for (const auto& [k, v] : env) std::printf("%s=%s\n", k.c_str(), v.c_str());
    for (std::size_t i = 0; i < argv.size(); ++i) std::printf("%s%s", i ? " " : "", argv[i].c_str());
    std::printf("\n");
    return kExitOk;
  }
  for (const auto& [k, v] : env) {
    if (v.empty())
      unsetenv(k.c_str());
    else
      setenv(k.c_str(), v.c_str(), 1);
  }
  std::fflush(stdout);
  std::vector<char*> cargv;
  for (auto& x : argv) cargv.push_back(x.data());
  cargv.push_back(nullptr);
  execvp(exe.c_str(), cargv.data());
  throw InputError("cannot start '" + exe + "' (" + std::string(std::strerror(errno)) +
                   "): install ParaView (Debian: apt-get install paraview) or give its path with --paraview");
}

}  // namespace varsph
