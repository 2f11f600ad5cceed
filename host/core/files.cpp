#include "core/files.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/fault.h"

namespace sdfbrick {

std::string read_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path.string() + ": cannot read: " + std::strerror(errno));
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) throw InputError(path.string() + ": read error");
    return ss.str();
}

void write_via_temp(const std::filesystem::path& path, const std::function<void(const std::filesystem::path&)>& write) {
    std::filesystem::path tmp = path;
    tmp.replace_filename(fmt::format(".{}.tmp-{}{}", path.stem().string(), ::getpid(), path.extension().string()));
    try {
        if (fault::should_fail(fault::Point::write)) {
            throw InputError(path.string() + ": cannot write: " + fault::describe(fault::Point::write, std::nullopt));
        }
        write(tmp);
        std::error_code ec;
        std::filesystem::rename(tmp, path, ec);
        if (ec) throw InputError(path.string() + ": cannot write: " + ec.message());
    } catch (...) {
        std::error_code ignored;
        std::filesystem::remove(tmp, ignored);
        throw;
    }
}

void write_file_atomic(const std::filesystem::path& path, std::string_view content) {
    write_via_temp(path, [&](const std::filesystem::path& tmp) {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw InputError(path.string() + ": cannot write: " + std::strerror(errno));
        out.write(content.data(), static_cast<std::streamsize>(content.size()));
        out.close();
        if (!out) throw InputError(path.string() + ": write failed: " + std::strerror(errno));
    });
}

}  // namespace sdfbrick
