#include "sweep/row.h"

#include <cstdint>
#include <limits>
#include <type_traits>

#include <fmt/format.h>

#include "core/errors.h"

namespace sdfbrick::sweep {

namespace {

using nlohmann::json;

template <class T>
json value_json(const T& v) {
    return json(v);
}
template <class T>
json value_json(const std::optional<T>& v) {
    return v ? json(*v) : json(nullptr);
}

// A value of the type the column holds, strictly: no integer from a fraction or a negative number,
// none out of its type's range (json's own conversions would wrap or truncate).
template <class T>
void read_value(const json& j, T& v) {
    if constexpr (std::is_same_v<T, bool>) {
        if (!j.is_boolean()) throw InputError("expected true or false");
    } else if constexpr (std::is_integral_v<T> && std::is_unsigned_v<T>) {
        if (!j.is_number_unsigned() || j.get<std::uint64_t>() > std::numeric_limits<T>::max())
            throw InputError(fmt::format("expected an integer in [0, {}]", std::numeric_limits<T>::max()));
    } else if constexpr (std::is_integral_v<T>) {
        if (!j.is_number_integer() || j.get<std::int64_t>() < std::numeric_limits<T>::min() ||
            j.get<std::int64_t>() > std::numeric_limits<T>::max())
            throw InputError(fmt::format("expected an integer in [{}, {}]", std::numeric_limits<T>::min(), std::numeric_limits<T>::max()));
    } else if constexpr (std::is_floating_point_v<T>) {
        if (!j.is_number()) throw InputError("expected a number");
    } else if constexpr (std::is_same_v<T, std::string>) {
        if (!j.is_string()) throw InputError("expected a string");
    }
    v = j.get<T>();
}
template <class T>
void read_value(const json& j, std::optional<T>& v) {
    if (j.is_null())
        v.reset();
    else
        v = j.get<T>();
}

// Where a column's value lives: the row itself or one of its optional parts.
template <class Part>
struct Place {
    std::function<const Part*(const SweepRow&)> find;  // null when the row lacks the part
    std::function<Part&(SweepRow&)> make;              // the part, created when absent
};

Place<SweepRow> whole_row() {
    return {[](const SweepRow& r) { return &r; }, [](SweepRow& r) -> SweepRow& { return r; }};
}

template <class Outer, class Part>
Place<Part> part(const Place<Outer>& outer, std::optional<Part> Outer::*member) {
    return {[outer, member](const SweepRow& r) -> const Part* {
                const Outer* o = outer.find(r);
                return o && o->*member ? &*(o->*member) : nullptr;
            },
            [outer, member](SweepRow& r) -> Part& {
                std::optional<Part>& p = outer.make(r).*member;
                if (!p) p.emplace();
                return *p;
            }};
}

// field: a callable giving the value's reference in a Part (const or not).
template <class Part, class Field>
Column column(std::string name, const Place<Part>& place, Field field, bool csv = true) {
    return {std::move(name), csv,
            [place, field](const SweepRow& r) -> std::optional<json> {
                const Part* p = place.find(r);
                if (!p) return std::nullopt;
                return value_json(field(*p));
            },
            [place, field](SweepRow& r, const json& j) { read_value(j, field(place.make(r))); }};
}

template <class Part, class T>
Column column(std::string name, const Place<Part>& place, T Part::*member, bool csv = true) {
    return column(std::move(name), place, [member](auto& p) -> auto& { return p.*member; }, csv);
}

// NAME_ms, NAME_min_ms, NAME_max_ms, NAME_cv: a spread's median, min, max and cv.
void add_spread(std::vector<Column>& c, const std::string& name, const Place<PointResults>& results,
                measure::Spread PointResults::*spread) {
    c.push_back(column(name + "_ms", results, [spread](auto& r) -> auto& { return (r.*spread).median; }));
    c.push_back(column(name + "_min_ms", results, [spread](auto& r) -> auto& { return (r.*spread).min; }));
    c.push_back(column(name + "_max_ms", results, [spread](auto& r) -> auto& { return (r.*spread).max; }));
    c.push_back(column(name + "_cv", results, [spread](auto& r) -> auto& { return (r.*spread).cv; }));
}

void add_parameters(std::vector<Column>& c, const Place<SweepRow>& row) {
    c.insert(c.end(), {column("index", row, &SweepRow::index), column("scene", row, &SweepRow::scene),
                       column("scene_file", row, &SweepRow::scene_file), column("device", row, &SweepRow::device),
                       column("vendor", row, &SweepRow::vendor), column("driver", row, &SweepRow::driver),
                       column("platform", row, &SweepRow::platform),
                       column("brick_size", row, &SweepRow::brick_size),
                       column("tolerance", row, &SweepRow::tolerance), column("chunk", row, &SweepRow::chunk),
                       column("group", row, &SweepRow::group), column("trace_group", row, &SweepRow::trace_group),
                       column("cull", row, &SweepRow::cull), column("format", row, &SweepRow::format),
                       column("samples", row, &SweepRow::samples), column("method", row, &SweepRow::method),
                       column("normals", row, &SweepRow::normals), column("width", row, &SweepRow::width),
                       column("height", row, &SweepRow::height)});
}

void add_outcome(std::vector<Column>& c, const Place<SweepRow>& row, const Place<PointResults>& results) {
    c.push_back(column("status", row, &SweepRow::status));
    c.push_back(column("error", part(row, &SweepRow::error), [](auto& text) -> auto& { return text; }));
    c.push_back(column("repeats", row, &SweepRow::repeats));
    c.push_back(column("identical", results, &PointResults::identical));
    c.push_back(column("bricks", results, &PointResults::bricks));
    c.push_back(column("pool_bytes", results, &PointResults::pool_bytes));
    c.push_back(column("check_error_max", results, &PointResults::check_error_max));
    c.push_back(column("levels", results, &PointResults::levels));
    c.push_back(column("edit_evaluations", results, &PointResults::edit_evaluations));
    c.push_back(column("memory_bytes", results, &PointResults::memory_bytes));
}

void add_times(std::vector<Column>& c, const Place<PointResults>& results) {
    add_spread(c, "build", results, &PointResults::build_ms);
    add_spread(c, "trace", results, &PointResults::trace_ms);
    c.push_back(column("bvh_ms", results, &PointResults::bvh_ms));
    for (std::size_t i = 0; i < measure::kConstructionStages.size(); ++i)
        c.push_back(column(fmt::format("stage_{}_ms", to_string(measure::kConstructionStages[i])), results,
                           [i](auto& r) -> auto& { return r.stage_ms[i]; }));
}

void add_rates(std::vector<Column>& c, const Place<PointResults>& results) {
    const Place<EvaluateOccupancy> evaluate = part(results, &PointResults::evaluate);
    c.push_back(column("evaluate_local_bytes", evaluate, &EvaluateOccupancy::local_bytes));
    c.push_back(column("evaluate_registers", evaluate, &EvaluateOccupancy::registers));
    c.push_back(column("evaluate_groups_per_cu", evaluate, &EvaluateOccupancy::groups_per_cu));
    c.push_back(column("evaluate_resident_groups", evaluate, &EvaluateOccupancy::resident_groups));
    c.push_back(column("evaluate_occupancy", evaluate, &EvaluateOccupancy::occupancy));
    c.push_back(column("evaluate_waves", evaluate, &EvaluateOccupancy::waves));
    c.push_back(column("evaluations_per_second", results, &PointResults::evaluations_per_second));
    const Place<WriteBandwidth> write = part(results, &PointResults::write);
    c.push_back(column("write_gbps", write, &WriteBandwidth::gbps));
    c.push_back(column("bandwidth_fraction", write, &WriteBandwidth::fraction));
    c.push_back(column("peak_bandwidth_gbps", results, &PointResults::peak_bandwidth_gbps));
    c.push_back(column("peak_fma_gflops", results, &PointResults::peak_fma_gflops));
}

void add_accuracy(std::vector<Column>& c, const Place<PointResults>& results) {
    const Place<PointAccuracy> accuracy = part(results, &PointResults::accuracy);
    c.push_back(column("mismatch", accuracy, &PointAccuracy::mismatch));
    c.push_back(column("depth_mean", accuracy, &PointAccuracy::depth_mean));
    c.push_back(column("depth_p99", accuracy, &PointAccuracy::depth_p99));
    c.push_back(column("normal_mean", accuracy, &PointAccuracy::normal_mean));
    c.push_back(column("normal_p99", accuracy, &PointAccuracy::normal_p99));
    c.push_back(column("psnr", accuracy, &PointAccuracy::psnr));
}

std::string cell(const std::optional<json>& value) {
    if (!value || value->is_null()) return "";
    const json& v = *value;
    std::string s = v.is_string() ? v.get<std::string>() : v.is_boolean() ? (v.get<bool>() ? "1" : "0") : v.dump();
    if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
    std::string q = "\"";
    for (char ch : s) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
    return q + "\"";
}

}  // namespace

const std::vector<Column>& columns() {
    static const std::vector<Column> list = [] {
        const Place<SweepRow> row = whole_row();
        const Place<PointResults> results = part(row, &SweepRow::results);
        std::vector<Column> c;
        add_parameters(c, row);
        add_outcome(c, row, results);
        add_times(c, results);
        add_rates(c, results);
        add_accuracy(c, results);
        c.push_back(column("key", row, &SweepRow::key, false));
        return c;
    }();
    return list;
}

std::vector<std::string> csv_columns() {
    std::vector<std::string> names;
    for (const Column& c : columns())
        if (c.csv) names.push_back(c.name);
    return names;
}

json to_json(const SweepRow& row) {
    json j = json::object();
    for (const Column& c : columns())
        if (std::optional<json> v = c.get(row)) j[c.name] = std::move(*v);
    return j;
}

json to_json(const std::vector<SweepRow>& rows) {
    json j = json::array();
    for (const SweepRow& r : rows) j.push_back(to_json(r));
    return j;
}

SweepRow row_from_json(const json& j) {
    if (!j.is_object()) throw InputError("expected a row object");
    SweepRow row;
    for (const Column& c : columns()) {
        const auto it = j.find(c.name);
        if (it == j.end()) continue;
        try {
            c.set(row, *it);
        } catch (const InputError& e) {
            throw InputError(fmt::format("/{}: {}", c.name, e.what()));
        } catch (const json::exception&) {
            throw InputError(fmt::format("/{}: a value of the wrong type ({})", c.name, it->type_name()));
        }
    }
    return row;
}

std::string to_csv(const std::vector<SweepRow>& rows) {
    std::string out;
    for (const Column& c : columns())
        if (c.csv) out += (out.empty() ? "" : ",") + c.name;
    out += '\n';
    for (const SweepRow& r : rows) {
        std::string line;
        bool first = true;
        for (const Column& c : columns()) {
            if (!c.csv) continue;
            if (!first) line += ',';
            first = false;
            line += cell(c.get(r));
        }
        out += line + '\n';
    }
    return out;
}

}  // namespace sdfbrick::sweep
