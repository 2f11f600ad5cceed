// libFuzzer entry point: any bytes as two reports for `compare` (measure/compare.h), cut at the first
// NUL byte (or in the middle). Each pair is either refused with an InputError (one printable line)
// or compared into stage deltas and their text.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "core/errors.h"
#include "fuzz_check.h"
#include "measure/compare.h"
#include "scene/scene_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace sdfbrick;
    const std::string_view all(reinterpret_cast<const char*>(data), size);
    const std::size_t nul = all.find('\0'), cut = nul == std::string_view::npos ? size / 2 : nul;
    try {
        const nlohmann::json a = parse_json_text(all.substr(0, cut), "a.json");
        const nlohmann::json b = parse_json_text(all.substr(std::min(cut + 1, size)), "b.json");
        const auto deltas = measure::compare_reports(a, b, "a.json", "b.json");
        (void)measure::compare_text(deltas);
    } catch (const InputError& e) {
        fuzz::check_refusal(e.what());
    }
    return 0;
}
