// Options every verb shares (commands.h).
#include "cl/kernel_source.h"
#include "cli/commands.h"

namespace sdfbrick::cli {

void apply_global_options(const GlobalOptions& global) {
    if (global.kernel_dir) ocl::set_kernel_dir(std::filesystem::path(*global.kernel_dir));
}

TuningChoice open_tuning(const GlobalOptions& global) {
    TuningChoice c;
    if (global.no_tuning) return c;
    c.path = global.tuning_db ? std::optional<std::filesystem::path>(*global.tuning_db) : tune::TuningDb::default_path();
    if (c.path) c.db = tune::TuningDb::load(*c.path);
    return c;
}

}  // namespace sdfbrick::cli
