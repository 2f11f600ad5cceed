#include "measure/kernel_attributes.h"

#include <mutex>
#include <regex>
#include <sstream>
#include <utility>

#include <fmt/format.h>

#include "cl/cl_error.h"
#include "cl/device.h"
#include "cl/program.h"

namespace sdfbrick::measure {

namespace {

std::string kernel_name(cl_kernel kernel) {
    std::size_t size = 0;
    ocl::check(clGetKernelInfo(kernel, CL_KERNEL_FUNCTION_NAME, 0, nullptr, &size), "reading a kernel's name");
    std::string name(size, '\0');
    ocl::check(clGetKernelInfo(kernel, CL_KERNEL_FUNCTION_NAME, size, name.data(), nullptr), "reading a kernel's name");
    name.resize(name.find('\0') == std::string::npos ? name.size() : name.find('\0'));
    return name;
}

template <class T>
T work_group_info(cl_kernel kernel, const ocl::Device& device, cl_kernel_work_group_info param, const char* what,
                  const std::string& name) {
    T value{};
    ocl::check(clGetKernelWorkGroupInfo(kernel, device.id(), param, sizeof(value), &value, nullptr), [&] {
        return fmt::format("reading {} of kernel '{}' on {}", what, name, device.info().name);
    });
    return value;
}

// Parsed logs by program key (BuildRecord::key): the same key means the same device, driver, source
// and options, hence the same compiled code, so an entry never goes stale.
const std::map<std::string, PtxasFunction>& parsed_log(const ocl::BuildRecord& record) {
    static std::mutex mutex;
    static std::map<std::string, std::map<std::string, PtxasFunction>> parsed;
    const std::lock_guard lock(mutex);
    auto it = parsed.find(record.key);
    if (it == parsed.end()) {
        it = parsed.emplace(record.key, parse_nv_ptxas(record.log)).first;
    }
    return it->second;
}

}  // namespace

std::map<std::string, PtxasFunction> parse_nv_ptxas(std::string_view log) {
    static const std::regex entry(R"(Compiling entry function '([^']+)')");
    static const std::regex properties(R"(Function properties for (\S+))");
    static const std::regex spills(R"((\d+) bytes spill stores, (\d+) bytes spill loads)");
    static const std::regex used(R"(Used (\d+) registers)");
    std::map<std::string, PtxasFunction> functions;
    std::string current;     // the entry function being compiled
    std::string properties_of;  // whose "Function properties" block the following lines belong to
    std::istringstream lines{std::string(log)};
    for (std::string line; std::getline(lines, line);) {
        std::smatch match;
        if (std::regex_search(line, match, entry)) {
            current = match[1].str();
            properties_of.clear();
            functions[current];
        } else if (std::regex_search(line, match, properties)) {
            properties_of = match[1].str();
        } else if (current.empty()) {
            continue;
        } else if (std::regex_search(line, match, spills)) {
            if (properties_of == current) {
                functions[current].spill_store_bytes = std::stoull(match[1].str());
                functions[current].spill_load_bytes = std::stoull(match[2].str());
            }
        } else if (std::regex_search(line, match, used)) {
            functions[current].registers = std::stoi(match[1].str());
        }
    }
    return functions;
}

std::map<std::string, int> parse_nv_registers(std::string_view log) {
    std::map<std::string, int> registers;
    for (const auto& [name, function] : parse_nv_ptxas(log)) {
        if (function.registers) {
            registers.emplace(name, *function.registers);
        }
    }
    return registers;
}

KernelAttributes kernel_attributes(const ocl::Device& device, cl_kernel kernel) {
    KernelAttributes a;
    a.kernel = kernel_name(kernel);
    a.work_group_size_limit =
        work_group_info<std::size_t>(kernel, device, CL_KERNEL_WORK_GROUP_SIZE, "the work-group size limit", a.kernel);
    a.preferred_multiple = work_group_info<std::size_t>(kernel, device, CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE,
                                                        "the preferred work-group size multiple", a.kernel);
    a.local_mem_bytes = work_group_info<cl_ulong>(kernel, device, CL_KERNEL_LOCAL_MEM_SIZE, "the local memory size",
                                                  a.kernel);
    a.private_mem_bytes = work_group_info<cl_ulong>(kernel, device, CL_KERNEL_PRIVATE_MEM_SIZE,
                                                    "the private memory size", a.kernel);
    if (device.info().has_extension("cl_nv_device_attribute_query")) {
        cl_program program = nullptr;
        ocl::check(clGetKernelInfo(kernel, CL_KERNEL_PROGRAM, sizeof(program), &program, nullptr),
                   [&] { return fmt::format("reading the program of kernel '{}'", a.kernel); });
        if (const ocl::Program* known = device.find_program(program)) {
            const auto& functions = parsed_log(known->record());
            if (const auto it = functions.find(a.kernel); it != functions.end()) {
                a.registers = it->second.registers;
                a.spill_store_bytes = it->second.spill_store_bytes;
                a.spill_load_bytes = it->second.spill_load_bytes;
            }
        }
    }
    return a;
}

nlohmann::json to_json(const KernelAttributes& a) {
    const auto optional = [](const auto& value) { return value ? nlohmann::json(*value) : nlohmann::json(nullptr); };
    return {
        {"kernel", a.kernel},
        {"work_group_size_limit", a.work_group_size_limit},
        {"preferred_multiple", a.preferred_multiple},
        {"local_mem_bytes", a.local_mem_bytes},
        {"private_mem_bytes", a.private_mem_bytes},
        {"registers", optional(a.registers)},
        {"spill_store_bytes", optional(a.spill_store_bytes)},
        {"spill_load_bytes", optional(a.spill_load_bytes)},
    };
}

}  // namespace sdfbrick::measure
