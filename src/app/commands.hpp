#pragma once
// The subcommands of `varsph`, each in its own file.
#include <string>
#include <vector>

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
};

int command_run(const CommandArgs& a);
int command_info(const CommandArgs& a);
int command_sample(const CommandArgs& a);
int command_compare(const CommandArgs& a);
int command_paraview(const CommandArgs& a);

}  // namespace varsph
