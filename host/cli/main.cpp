// sdfbrick: the command line. Exit status 0 on success, 2 for bad input (a malformed scene, an
// unknown device, a bad option), 3 for a failed verdict (compare --gate: a regression), 1 for any
// other failure (an OpenCL error, ...). Every failure is one line on stderr.
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <exception>
#include <new>

#include <fmt/format.h>

#include "cl/kernel_source.h"
#include "cli/commands.h"
#include "core/errors.h"
#include "core/fault.h"
#include "core/files.h"
#include "core/quote.h"

int main(int argc, char** argv) {
    using namespace sdfbrick;
    CLI::App app{"sdfbrick: sparse signed-distance-field bricks from CSG edit lists, on any OpenCL device"};
    app.set_version_flag("--version", std::string("sdfbrick ") + SDFBRICK_VERSION);
    app.require_subcommand(1);
    app.fallthrough();
    cli::GlobalOptions global;
    app.add_option("-d,--device", global.device,
                   "OpenCL device(s): an index, gpu, cpu, accelerator, all, or part of a device or platform "
                   "name; comma-separated for several (default: $SDFBRICK_DEVICE, else the first GPU, else device 0)");
    app.add_option("--devices", global.devices,
                   "with several devices: replicate (each runs the whole job; results compared) or split (they "
                   "share one job: construction by subtrees, the trace by row bands; build and render)")
        ->capture_default_str();
    app.add_option("--kernel-dir", global.kernel_dir,
                   "load kernel sources from this directory instead of the copies built into the binary "
                   "(also $SDFBRICK_KERNEL_DIR)");
    app.add_option("--tuning-db", global.tuning_db,
                   "tuning database to read (and, for tune, to write); default: $SDFBRICK_TUNING_DB, else "
                   "$XDG_CONFIG_HOME/sdfbrick/tuning.json or ~/.config/sdfbrick/tuning.json");
    app.add_option("--allow-outside", global.allow_outside,
                   "a folder outside the scene file's own whose mesh files scenes may name (repeatable; "
                   "by default a scene reads meshes only from its own folder and below)");
    app.add_flag("--no-tuning", global.no_tuning, "ignore the tuning database: built-in defaults for every parameter not given");
    cli::add_devices_command(app, global);
    cli::add_scene_commands(app, global);
    cli::add_eval_command(app, global);
    cli::add_build_command(app, global);
    cli::add_render_command(app, global);
    cli::add_play_command(app, global);
    cli::add_sweep_commands(app, global);
    cli::add_tune_command(app, global);
    cli::add_export_commands(app, global);
    cli::add_compare_command(app);
    cli::add_stability_command(app, global);

    try {
        // A closed standard output would be reused by the next file opened, and what is meant for
        // the terminal would land in an output file.
        if (::fcntl(STDOUT_FILENO, F_GETFD) == -1) throw InputError("standard output is closed");
        fault::check();
        install_output_cleanup();  // a signal mid-write removes the temporary files it began
        app.parse(argc, argv);
        finish_stdout();
        return 0;
    } catch (const CLI::Success& e) {
        return app.exit(e);  // --help, --version
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "sdfbrick: %s (run with --help for usage)\n", escaped(e.what(), 300).c_str());
        return 2;
    } catch (const SettingError& e) {
        std::fprintf(stderr, "sdfbrick: %s\n", cli::setting_error_line(app, e).c_str());
        return 2;
    } catch (const InputError& e) {
        std::fprintf(stderr, "sdfbrick: %s\n", e.what());
        return 2;
    } catch (const VerdictFailure& e) {
        std::fprintf(stderr, "sdfbrick: %s\n", e.what());
        return 3;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "sdfbrick: error: out of host memory\n");
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sdfbrick: error: %s\n", e.what());
        return 1;
    }
}
