// The `varsph` command: run, info, sample, compare, study, paraview (CONTRACT.md). Exit codes: 0 ok,
// 1 internal error, 2 invalid input or usage, 3 numerical failure, 4 I/O failure, 130/143 interrupted.
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/commands.hpp"
#include "core/errors.hpp"
#include "parallel/collective.hpp"
#include "parallel/session.hpp"

int main(int argc, char** argv) {
  using namespace varsph;
  // MPI only when an MPI launcher started us (parallel/session.hpp); otherwise the serial program
  parallel::Session session(argc, argv);
  const bool root = session.world()->root();
  CLI::App app{"varsph: weakly-compressible SPH with variational time integration.\n"
               "Scenes are JSON files (docs/scene.md); results are VTU/PVD for ParaView.\n"
               "A scene that names no method keys runs the recommended engineering set-up (Wendland C2, Riemann "
               "dissipation, dummy walls, symplectic Euler at CFL 0.2); \"setup\": \"paper\" (or --set setup=paper) "
               "gives the paper's defaults (docs/scene.md \"Set-up\")."};
  app.set_version_flag("--version", std::string("varsph ") + VARSPH_VERSION + " (" + VARSPH_REAL_NAME + ")");
  app.require_subcommand(1);

  CommandArgs args;
  args.argv.assign(argv, argv + argc);
  args.comm = session.world();

  auto* run = app.add_subcommand("run", "Run a scene; writes DIR/NAME.pvd, frames/, diagnostics.csv, run.json");
  run->add_option("scene", args.scene, "Scene file (JSON)")->required();
  run->add_option("-o,--output", args.output, "Run directory (default runs/NAME)");
  run->add_option("--set", args.overrides, "Override a scene key: KEY=VALUE (VALUE as JSON), repeatable");
  run->add_option("--threads", args.threads, "OpenMP threads (default: one per core the load average says is "
                  "free, at least one; OMP_NUM_THREADS also sets it)")->check(CLI::PositiveNumber);
  run->add_option("--device", args.device,
                  "Where the steps run: cpu, cuda (an NVIDIA GPU), cuda_emulation (the CUDA backend's loops on the "
                  "CPU, for tests); sets execution.device (docs/gpu.md)");
  run->add_option("--restart", args.restart, "Continue from a checkpoint .h5");
  run->add_flag("--overwrite", args.overwrite, "Replace an existing non-empty run directory");
  run->add_flag("--quiet", args.quiet, "Print only errors");

  auto* info = app.add_subcommand("info", "Print the resolved parameters of a scene and what a run will cost "
                                           "(particles per body, memory, steps, wall time, disk) without running it");
  info->add_option("scene", args.scene, "Scene file (JSON)")->required();
  info->add_option("--set", args.overrides, "Override a scene key: KEY=VALUE");
  info->add_option("--threads", args.threads, "OpenMP threads of the calibration (default: as varsph run: one per free core)")
      ->check(CLI::PositiveNumber);
  info->add_option("--max-memory", args.limits.memory_gb, "Warn when the run needs more memory [GB] "
                   "(default: 80 % of this machine's)")->check(CLI::NonNegativeNumber);
  info->add_option("--max-disk", args.limits.disk_gb, "Warn when frames and checkpoints need more disk [GB] "
                   "(default: the free space here)")->check(CLI::NonNegativeNumber);
  info->add_option("--max-hours", args.limits.hours, "Warn when the run takes longer [h] (default 24)")
      ->check(CLI::PositiveNumber);
  info->add_option("--calibrate-max", args.limits.calibrate_max_particles, "Scenes planned above this many "
                   "particles are not sampled: a coarser copy is, and scaled (default 100000)")
      ->check(CLI::PositiveNumber);

  auto* sample = app.add_subcommand("sample", "Geometry only: write the sampled particles as VTU (with their body index) and print the count and the box of each body and the spacing statistics");
  sample->add_option("scene", args.scene, "Scene file (JSON)")->required();
  sample->add_option("-o,--output", args.output, "Output directory")->required();
  sample->add_option("--set", args.overrides, "Override a scene key: KEY=VALUE");
  sample->add_flag("--overwrite", args.overwrite, "Replace an existing non-empty directory");

  auto* compare = app.add_subcommand("compare", "Deviation between two runs (seed eq. 70): DIR/deviation.csv, DIR/deviation.pvd");
  compare->add_option("run_a", args.run_a, "Run directory A (or its .pvd)")->required();
  compare->add_option("run_b", args.run_b, "Run directory B (or its .pvd)")->required();
  compare->add_option("-o,--output", args.output, "Output directory (default RUN_A/post/deviation_vs_NAME)");
  compare->add_flag("--overwrite", args.overwrite, "Replace an existing non-empty output directory");
  compare->add_flag("--quiet", args.quiet, "Print only errors");

  StudyCli study_cli;
  auto* study = add_study_command(app, study_cli);

  auto* paraview = app.add_subcommand("paraview", "Open the ParaView GUI on a run: varsph plugin loaded, a state shown");
  paraview->add_option("run", args.run_a, "Run directory (or its .pvd)")->required();
  paraview->add_option("run_b", args.run_b, "Second run, for the deviation state");
  paraview->add_option("--state", args.state,
                       "free_surface | pressure (default) | deviation (default with RUN_B) | open_flow | elevation; NAME.pvsm for the XML "
                       "state; or a .py / .pvsm state file");
  paraview->add_option("--paraview", args.paraview_exe, "ParaView executable (default: paraview on PATH)");
  paraview->add_flag("--dry-run", args.dry_run, "Print the environment and command instead of starting ParaView");
  paraview->footer("Arguments after -- go to paraview (varsph paraview RUN -- --dr).");

  // `varsph paraview ... -- ARGS`: ARGS go to paraview untouched (split off before CLI11 sees them)
  if (argc > 1 && std::string(argv[1]) == "paraview")
    for (int i = 2; i < argc; ++i)
      if (std::string(argv[i]) == "--") {
        args.paraview_args.assign(argv + i + 1, argv + argc);
        argc = i;
        break;
      }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {  // every rank parses the same command line; rank 0 reports
    const int code = root ? app.exit(e) : (e.get_exit_code() == 0 ? 0 : 1);
    return code == 0 ? kExitOk : kExitInput;
  }
  // An error every rank agreed on (parallel/collective.hpp) is reported once and ends every rank
  // normally; one that reached main on some ranks only ends all of them at once (MPI_Abort), so that
  // none is left waiting for the others.
  auto fail = [&](int code, const char* what, const char* message) {
    const bool agreed = !session.distributed() || parallel::agreed_failure();
    if (root || !agreed) {
      if (session.distributed() && !agreed)
        std::fprintf(stderr, "varsph: rank %d: %s: %s\n", session.world()->rank(), what, message);
      else
        std::fprintf(stderr, "varsph: %s: %s\n", what, message);
    }
    if (!agreed) session.abort(code);
    return code;
  };
  try {
    if (*run) return command_run(args);
    // the other commands read and write single files: rank 0 does them alone
    if (!root) return kExitOk;
    if (*info) return command_info(args);
    if (*sample) return command_sample(args);
    if (*compare) return command_compare(args);
    if (*study) {
      study_cli.ratio_given = study->count("--ratio") > 0;
      return command_study(study_cli, args.argv);
    }
    if (*paraview) return command_paraview(args);
  } catch (const InputError& e) {
    return fail(kExitInput, "error", e.what());
  } catch (const NumericalError& e) {
    return fail(kExitNumerical, "numerical failure", e.what());
  } catch (const IoError& e) {
    return fail(kExitIo, "I/O error", e.what());
  } catch (const std::exception& e) {
    return fail(kExitInternal, "internal error (please report)", e.what());
  }
  return kExitInternal;
}
