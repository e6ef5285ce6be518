#pragma once
// The subcommands of `varsph`, each in its own file.
#include <memory>
#include <string>
#include <vector>

#include "parallel/communicator.hpp"
#include "sim/run_estimate.hpp"
#include "study/study_options.hpp"

namespace CLI {
class App;
}

namespace varsph {

struct CommandArgs {
  std::vector<std::string> argv;
  std::string scene, output, restart;
  std::string run_a, run_b;  // compare
  std::vector<std::string> overrides;
  int threads = 0;
  std::string device;  // run --device: execution.device override (cpu | cuda | cuda_emulation)
  bool overwrite = false, quiet = false;
  std::string state, paraview_exe;  // paraview
  std::vector<std::string> paraview_args;
  bool dry_run = false;             // paraview
  EstimateLimits limits;            // info: thresholds of the run estimate
  std::shared_ptr<parallel::Communicator> comm;  // all ranks of the run (one: the serial program)
};

int command_run(const CommandArgs& a);
int command_info(const CommandArgs& a);
int command_sample(const CommandArgs& a);
int command_compare(const CommandArgs& a);
int command_paraview(const CommandArgs& a);

// `varsph study` has its own options (src/app/command_study.cpp)
struct StudyCli {
  study::StudyOptions o;
  std::vector<std::string> scenes, windows;
  std::string output, refine = "both", ratio = "2";
  bool ratio_given = false, no_plots = false, no_extra_probes = false;
};
CLI::App* add_study_command(CLI::App& app, StudyCli& c);
int command_study(StudyCli& c, const std::vector<std::string>& argv);

}  // namespace varsph
