#include "core/fault.h"

#include <charconv>
#include <cstdlib>
#include <mutex>
#include <vector>

#include <fmt/format.h>

#include "core/errors.h"

namespace sdfbrick::fault {

namespace {

struct Item {
    Point point;
    std::optional<std::size_t> device;
    std::size_t nth = 0;
    std::size_t seen = 0;
};

constexpr Point kPoints[] = {Point::alloc, Point::build, Point::launch, Point::write, Point::signal};

std::size_t parse_number(std::string_view text, std::string_view item, std::size_t least) {
    std::size_t value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size() || value < least) {
        throw InputError(fmt::format("{}: item '{}': expected a whole number >= {}, got '{}'", kEnv, item, least,
                                     text));
    }
    return value;
}

Item parse_item(std::string_view item) {
    const std::size_t colon = item.rfind(':');
    if (colon == std::string_view::npos) {
        throw InputError(fmt::format("{}: item '{}' is not POINT[@DEVICE]:N", kEnv, item));
    }
    std::string_view head = item.substr(0, colon);
    Item parsed{};
    parsed.nth = parse_number(item.substr(colon + 1), item, 1);
    if (const std::size_t at = head.find('@'); at != std::string_view::npos) {
        parsed.device = parse_number(head.substr(at + 1), item, 0);
        head = head.substr(0, at);
    }
    bool known = false;
    for (Point p : kPoints) {
        if (head == point_name(p)) {
            parsed.point = p;
            known = true;
        }
    }
    if (!known) {
        throw InputError(fmt::format("{}: item '{}': unknown point '{}' (alloc, build, launch, write, signal)", kEnv, item,
                                     head));
    }
    return parsed;
}

struct State {
    std::mutex mutex;
    bool loaded = false;
    std::vector<Item> items;
};

State& state() {
    static State s;
    return s;
}

std::vector<Item> parse_env() {
    const char* value = std::getenv(kEnv);
    std::vector<Item> items;
    if (value == nullptr) return items;
    std::string_view rest(value);
    while (!rest.empty()) {
        const std::size_t comma = rest.find(',');
        const std::string_view item = rest.substr(0, comma);
        if (!item.empty()) items.push_back(parse_item(item));
        rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
    }
    return items;
}

}  // namespace

std::string_view point_name(Point point) {
    switch (point) {
        case Point::alloc: return "alloc";
        case Point::build: return "build";
        case Point::launch: return "launch";
        case Point::write: return "write";
        case Point::signal: return "signal";
    }
    return "?";
}

namespace {

// Loads the items once (the caller holds the mutex); a malformed value is reported once, then
// injection stays off.
void load(State& s) {
    if (s.loaded) return;
    s.loaded = true;
    s.items = parse_env();
}

}  // namespace

void check() {
    State& s = state();
    const std::lock_guard lock(s.mutex);
    load(s);
}

bool should_fail(Point point, std::optional<std::size_t> device) {
    State& s = state();
    const std::lock_guard lock(s.mutex);
    load(s);
    bool fail = false;
    for (Item& item : s.items) {
        if (item.point != point || (item.device && item.device != device)) continue;
        fail = ++item.seen == item.nth || fail;
    }
    return fail;
}

void reset() {
    State& s = state();
    const std::lock_guard lock(s.mutex);
    s.loaded = false;
    s.items.clear();
}

std::string describe(Point point, std::optional<std::size_t> device) {
    return device ? fmt::format("injected fault ({} on device {}, {})", point_name(point), *device, kEnv)
                  : fmt::format("injected fault ({}, {})", point_name(point), kEnv);
}

}  // namespace sdfbrick::fault
