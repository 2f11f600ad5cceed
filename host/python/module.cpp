// The Python module `sdfbrick` (pybind11) over the library: the devices, scenes, and a Context that
// holds opened devices and an executor whose lanes keep their state (programs, memory, image buffers)
// from call to call. build, render, sweep, stability and tune give the reports of the CLI's --json
// (the same library functions make them); bad input raises sdfbrick.InputError (a ValueError), a
// device failure sdfbrick.DeviceError (a RuntimeError), each with the CLI's one-line message. The GIL
// is released while devices work. docs/python.md.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "cl/cl_error.h"
#include "cl/device.h"
#include "cl/kernel_source.h"
#include "core/errors.h"
#include "core/fault.h"
#include "core/files.h"
#include "core/quote.h"
#include "pipeline/command_report.h"
#include "pipeline/executor.h"
#include "pipeline/play.h"
#include "scene/edit_log.h"
#include "reference/accuracy.h"
#include "scene/generate.h"
#include "scene/scene_info.h"
#include "scene/scene_json.h"
#include "scene/to_device.h"
#include "sweep/grid.h"
#include "sweep/runner.h"
#include "sweep/stability.h"
#include "tune/apply.h"
#include "tune/kernels.h"
#include "tune/tuner.h"
#include "tune/tuning_db.h"

namespace py = pybind11;

namespace sdfbrick::python {

namespace {

// ---- errors ----

PyObject* input_error = nullptr;   // sdfbrick.InputError (ValueError)
PyObject* device_error = nullptr;  // sdfbrick.DeviceError (RuntimeError)

// The keyword argument that sets a library setting (SettingError::setting()), where the two differ.
std::string argument_of(const std::string& setting) {
    if (setting == "leaf_size") return "brick_size";
    if (setting == "max_leaf_size") return "max_brick_size";
    if (setting == "eval_group") return "group";
    if (setting == "eval_lanes") return "lanes";
    if (setting == "eval_registers") return "eval_max_registers";
    return setting;
}

// Raises sdfbrick.InputError with message; for a setting, the message is "ARGUMENT: message" and the
// exception has the attributes `setting` (the library's name) and `argument` (the keyword).
void raise_input_error(const std::string& message, const std::string* setting) {
    const py::handle type(input_error);
    const std::string argument = setting ? argument_of(*setting) : std::string();
    py::object e = type(setting ? argument + ": " + message : message);
    e.attr("setting") = setting ? py::object(py::str(*setting)) : py::object(py::none());
    e.attr("argument") = setting ? py::object(py::str(argument)) : py::object(py::none());
    PyErr_SetObject(input_error, e.ptr());
}

void translate(std::exception_ptr p) {
    try {
        if (p) std::rethrow_exception(p);
    } catch (const SettingError& e) {
        raise_input_error(e.what(), &e.setting());
    } catch (const InputError& e) {
        raise_input_error(e.what(), nullptr);
    } catch (const ocl::ClError& e) {
        PyErr_SetString(device_error, e.what());
    }
}

// ---- JSON and Python values ----

py::str text(std::string_view s) {
    return py::reinterpret_steal<py::str>(PyUnicode_DecodeUTF8(s.data(), static_cast<Py_ssize_t>(s.size()), "replace"));
}

// Reports as Python values: objects are dicts, arrays lists; a number that is not finite (which the
// CLI's JSON writes as null) is None.
py::object to_python(const nlohmann::json& j) {
    using T = nlohmann::json::value_t;
    switch (j.type()) {
    case T::boolean: return py::bool_(j.get<bool>());
    case T::number_integer: return py::int_(j.get<std::int64_t>());
    case T::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case T::number_float: {
        const double d = j.get<double>();
        return std::isfinite(d) ? py::object(py::float_(d)) : py::object(py::none());
    }
    case T::string: return text(j.get_ref<const std::string&>());
    case T::array: {
        py::list l;
        for (const nlohmann::json& e : j) l.append(to_python(e));
        return l;
    }
    case T::object: {
        py::dict d;
        for (const auto& [k, v] : j.items()) d[text(k)] = to_python(v);
        return d;
    }
    default: return py::none();
    }
}

std::string type_name(py::handle h) { return py::str(py::type::handle_of(h).attr("__name__")); }

// A Python value as JSON (dicts with str keys, lists, tuples, str, int, float, bool, None, path-like
// objects and NumPy scalars). origin and path name the value in messages, as the scene reader does.
nlohmann::json from_python(py::handle h, const std::string& origin, const std::string& path = "") {
    const std::string where = fmt::format("{}: {}", origin, path.empty() ? "/" : path);
    if (h.is_none()) return nullptr;
    if (PyBool_Check(h.ptr())) return h.cast<bool>();
    if (PyUnicode_Check(h.ptr())) return h.cast<std::string>();
    // NumPy arrays and scalars: as the lists and Python numbers they hold
    if (!PyLong_Check(h.ptr()) && !PyFloat_Check(h.ptr()) && !PyDict_Check(h.ptr()) && !PyList_Check(h.ptr()) &&
        !PyTuple_Check(h.ptr()) && py::hasattr(h, "tolist"))
        return from_python(h.attr("tolist")(), origin, path);
    if (PyLong_Check(h.ptr()) || (!PyFloat_Check(h.ptr()) && py::hasattr(h, "__index__"))) {
        const py::int_ i = py::reinterpret_steal<py::int_>(PyNumber_Index(h.ptr()));
        int overflow = 0;
        const long long v = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
        if (overflow == 0) return v;
        if (overflow > 0) {
            const unsigned long long u = PyLong_AsUnsignedLongLong(i.ptr());
            if (!PyErr_Occurred()) return u;
            PyErr_Clear();
        }
        throw InputError(fmt::format("{}: integer out of range", where));
    }
    if (PyFloat_Check(h.ptr()) || py::hasattr(h, "__float__")) {
        const double d = py::float_(py::reinterpret_borrow<py::object>(h));
        if (!std::isfinite(d)) throw InputError(fmt::format("{}: number is not finite: {}", where, d));
        return d;
    }
    if (PyDict_Check(h.ptr())) {
        nlohmann::json j = nlohmann::json::object();
        for (const auto& [k, v] : py::reinterpret_borrow<py::dict>(h)) {
            if (!PyUnicode_Check(k.ptr()))
                throw py::type_error(fmt::format("{}: keys must be str, got {}", where, type_name(k)));
            const std::string key = k.cast<std::string>();
            j[key] = from_python(v, origin, path + "/" + key);
        }
        return j;
    }
    if (PyList_Check(h.ptr()) || PyTuple_Check(h.ptr())) {
        nlohmann::json j = nlohmann::json::array();
        std::size_t i = 0;
        for (const py::handle v : h) j.push_back(from_python(v, origin, fmt::format("{}/{}", path, i++)));
        return j;
    }
    if (py::hasattr(h, "__fspath__")) return py::module_::import("os").attr("fspath")(h).cast<std::string>();
    throw py::type_error(fmt::format("{}: cannot be written as JSON: {}", where, type_name(h)));
}

// ---- scenes ----

// A scene as loaded or made; calls evaluate it at a time (scene_at). Copies share the scene, and with
// it the grids of its mesh edits, converted once.
struct PyScene {
    std::shared_ptr<const Scene> scene;
    std::optional<std::string> file;  // where it was loaded from

    static PyScene load(const std::filesystem::path& path) {
        return {std::make_shared<const Scene>(load_scene(path)), path.string()};
    }
    static PyScene from_dict(const py::dict& d, const std::optional<std::filesystem::path>& base) {
        const nlohmann::json j = from_python(d, "<dict>");
        return {std::make_shared<const Scene>(scene_from_json(j, "<dict>", base.value_or(std::filesystem::path()))), {}};
    }
    static PyScene from_json(const std::string& text, const std::optional<std::filesystem::path>& base) {
        return {std::make_shared<const Scene>(parse_scene(text, "<string>", base.value_or(std::filesystem::path()))), {}};
    }
    Scene at(const std::optional<double>& time) const { return scene_at(*scene, time.value_or(scene->time)); }
};

// ---- keyword arguments ----

// The keyword arguments of one call, taken by name and type; what is left is refused (TypeError
// naming it, as Python does for an unknown keyword).
class Kwargs {
public:
    Kwargs(const py::kwargs& kwargs, std::string function) : function_(std::move(function)) {
        for (const auto& [k, v] : kwargs) values_[k.cast<std::string>()] = py::reinterpret_borrow<py::object>(v);
    }

    std::optional<double> number(const std::string& name) {
        const std::optional<py::object> v = take(name);
        if (!v) return std::nullopt;
        if (PyBool_Check(v->ptr()) || !(PyFloat_Check(v->ptr()) || PyLong_Check(v->ptr()) || py::hasattr(*v, "__float__")) ||
            PyUnicode_Check(v->ptr()))
            type_error(name, "a number", *v);
        const double d = py::float_(*v);
        if (!std::isfinite(d)) throw SettingError(name, fmt::format("{} must be a finite number, got {}", name, d));
        return d;
    }
    std::optional<int> integer(const std::string& name) {
        const std::optional<py::object> v = take(name);
        if (!v) return std::nullopt;
        if (PyBool_Check(v->ptr()) || !(PyLong_Check(v->ptr()) || (py::hasattr(*v, "__index__") && !PyFloat_Check(v->ptr()))))
            type_error(name, "an int", *v);
        const py::int_ i = py::reinterpret_steal<py::int_>(PyNumber_Index(v->ptr()));
        int overflow = 0;
        const long long x = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
        if (overflow != 0 || x < std::numeric_limits<int>::min() || x > std::numeric_limits<int>::max())
            throw SettingError(name, fmt::format("{} is out of range", name));
        return static_cast<int>(x);
    }
    std::optional<bool> boolean(const std::string& name) {
        const std::optional<py::object> v = take(name);
        if (!v) return std::nullopt;
        if (!PyBool_Check(v->ptr()) && type_name(*v) != "bool_") type_error(name, "a bool", *v);
        return v->cast<bool>();
    }
    std::optional<std::string> string(const std::string& name) {
        const std::optional<py::object> v = take(name);
        if (!v) return std::nullopt;
        if (!PyUnicode_Check(v->ptr())) type_error(name, "a str", *v);
        return v->cast<std::string>();
    }
    // A str, or a list or tuple of them.
    std::optional<std::vector<std::string>> strings(const std::string& name) {
        const std::optional<py::object> v = take(name);
        if (!v) return std::nullopt;
        if (PyUnicode_Check(v->ptr())) return std::vector<std::string>{v->cast<std::string>()};
        if (!PyList_Check(v->ptr()) && !PyTuple_Check(v->ptr())) type_error(name, "a str or a list of str", *v);
        std::vector<std::string> out;
        for (const py::handle e : *v) {
            if (!PyUnicode_Check(e.ptr())) type_error(name, "a str or a list of str", py::reinterpret_borrow<py::object>(e));
            out.push_back(e.cast<std::string>());
        }
        return out;
    }
    std::optional<py::object> object(const std::string& name) { return take(name); }

    // Refuses what no take asked for.
    void done() const {
        if (!values_.empty())
            throw py::type_error(fmt::format("{}() got an unexpected keyword argument '{}'", function_, values_.begin()->first));
    }

private:
    std::optional<py::object> take(const std::string& name) {
        const auto it = values_.find(name);
        if (it == values_.end()) return std::nullopt;
        py::object v = std::move(it->second);
        values_.erase(it);
        if (v.is_none()) return std::nullopt;  // None: the default
        return v;
    }
    [[noreturn]] void type_error(const std::string& name, const char* expected, const py::object& v) const {
        throw py::type_error(fmt::format("{}(): {} must be {}, got {}", function_, name, expected, type_name(v)));
    }

    std::string function_;
    std::map<std::string, py::object> values_;
};

// The build settings of a call: the names of the report's "settings" (so that a report's settings
// can be passed back), and tolerance_voxels.
// The trace keywords of render and play: image size, mode, method, normals, work-group, shading rays.
struct TraceArgs {
    render::TraceSettings trace;
    std::string mode = "normals";
    bool group_given = false, registers_given = false;
};

render::Method method_argument(const std::string& value) {
    const auto m = render::method_from_string(value);
    if (!m) throw SettingError("method", fmt::format("method must be {}, got \"{}\"", render::method_names(), value));
    return *m;
}

TraceArgs take_trace(Kwargs& k) {
    TraceArgs t;
    render::TraceSettings& trace = t.trace;
    if (const auto v = k.integer("width")) trace.width = *v;
    if (const auto v = k.integer("height")) trace.height = *v;
    if (const auto v = k.string("mode")) t.mode = *v;
    if (const auto v = k.string("method")) trace.method = method_argument(*v);
    if (const auto v = k.string("normals")) {
        const auto n = render::normals_from_string(*v);
        if (!n) throw SettingError("normals", fmt::format("normals must be central, tetra or continuous, got \"{}\"", *v));
        trace.normals = *n;
    }
    if (const auto v = k.integer("group_x")) {
        trace.group_x = *v;
        t.group_given = true;
    }
    if (const auto v = k.integer("group_y")) {
        trace.group_y = *v;
        t.group_given = true;
    }
    if (const auto v = k.integer("shadow_rays")) trace.shadow_rays = *v;
    if (const auto v = k.integer("ao_rays")) trace.ao_rays = *v;
    if (const auto v = k.integer("max_registers")) {
        trace.max_registers = *v;
        t.registers_given = true;
    }
    if (trace.max_registers < 0 || trace.max_registers > 255)
        throw SettingError("max_registers", fmt::format("max_registers must lie in 0..255, got {}", trace.max_registers));
    if (!pipeline::is_render_mode(t.mode))
        throw SettingError("mode", fmt::format("mode must be normals, depth, shaded, steps or bricks, got \"{}\"", t.mode));
    if (trace.shadow_rays < 0 || trace.shadow_rays > 64)
        throw SettingError("shadow_rays", fmt::format("shadow_rays must lie in 0..64, got {}", trace.shadow_rays));
    if (trace.ao_rays < 0 || trace.ao_rays > 64)
        throw SettingError("ao_rays", fmt::format("ao_rays must lie in 0..64, got {}", trace.ao_rays));
    trace.shade = t.mode == "shaded";
    validate_image_size(trace.width, trace.height);
    return t;
}

struct BuildArgs {
    construct::BuildSettings settings;
    tune::Given given;
};

BuildArgs take_build_settings(Kwargs& k) {
    BuildArgs a;
    construct::BuildSettings& s = a.settings;
    const std::optional<double> brick_size = k.number("brick_size");
    if (brick_size) s.leaf_size = *brick_size;
    if (const auto v = k.integer("levels")) s.levels = *v;
    if (const auto v = k.integer("branching")) s.branching = *v;
    if (const auto v = k.integer("samples")) s.samples = *v;
    if (const auto v = k.string("format")) {
        const auto f = construct::format_from_string(*v);
        if (!f) throw SettingError("format", fmt::format("format must be int8, int16 or float, got \"{}\"", *v));
        s.format = *f;
    }
    if (const auto v = k.number("band_voxels")) s.band_voxels = *v;
    if (const auto v = k.number("guard")) s.guard = *v;
    if (const auto v = k.integer("chunk")) {
        s.chunk = *v;
        a.given.chunk = true;
    }
    if (const auto v = k.integer("group")) {
        s.eval_group = *v;
        a.given.group = true;
    }
    if (const auto v = k.integer("eval_max_registers")) {
        s.eval_registers = *v;
        a.given.eval_registers = true;
    }
    if (const auto v = k.integer("lanes")) s.eval_lanes = *v;
    if (const auto v = k.integer("count_parts")) s.count_parts = *v;
    if (const auto v = k.integer("count_splits")) s.count_splits = *v;
    if (const auto v = k.integer("count_untested")) s.count_untested = *v;
    if (const auto v = k.boolean("cull")) s.cull = *v;
    if (const auto v = k.boolean("skip_far")) s.skip_far = *v;
    if (const auto v = k.integer("cull_siblings")) s.cull_siblings = *v;
    if (const auto v = k.integer("apron_share_edits")) s.apron_share_edits = *v;
    if (const auto v = k.boolean("dependencies")) s.dependencies = *v;
    if (const auto v = k.number("max_brick_size")) s.max_leaf_size = *v;
    const std::optional<double> tolerance = k.number("tolerance");
    const std::optional<double> tolerance_voxels = k.number("tolerance_voxels");
    if (tolerance && tolerance_voxels) throw py::type_error("tolerance and tolerance_voxels exclude each other");
    if (tolerance) {
        if (*tolerance < 0.0)
            throw SettingError("tolerance", fmt::format("tolerance must be >= 0 (0: uniform), got {}", *tolerance));
        s.tolerance = *tolerance;
    }
    if (tolerance_voxels) {
        if (!(*tolerance_voxels > 0.0))
            throw SettingError("tolerance_voxels", fmt::format("tolerance_voxels must be > 0, got {}", *tolerance_voxels));
        s.tolerance = *tolerance_voxels * s.voxel();
    }
    if (s.adaptive() && !brick_size) s.leaf_size = construct::auto_leaf_size(s.tolerance, s.layout());
    return a;
}

// repeat (1..1000) and warmup (0..100; default 1 with repeat > 1, else 0).
std::pair<int, int> take_repeats(Kwargs& k) {
    const int repeat = k.integer("repeat").value_or(1);
    if (repeat < 1 || repeat > 1000) throw SettingError("repeat", fmt::format("repeat must lie in 1..1000, got {}", repeat));
    const int warmup = k.integer("warmup").value_or(repeat > 1 ? 1 : 0);
    if (warmup < 0 || warmup > 100) throw SettingError("warmup", fmt::format("warmup must lie in 0..100, got {}", warmup));
    return {repeat, warmup};
}

// ---- arrays ----

// What a render gives back besides its report; the arrays view it (no copy) and keep it alive.
struct RenderData {
    RenderBuffer buffer;
    Image picture;
    std::optional<RenderBuffer> reference;
    Image reference_picture, difference;
};

template <class T>
py::array view(const std::shared_ptr<RenderData>& data, const T* first, std::vector<py::ssize_t> shape,
               std::vector<py::ssize_t> strides) {
    const py::capsule owner(new std::shared_ptr<RenderData>(data),
                            [](void* p) { delete static_cast<std::shared_ptr<RenderData>*>(p); });
    return py::array_t<T>(std::move(shape), std::move(strides), first, owner);
}

py::array image_view(const std::shared_ptr<RenderData>& data, const Image& im) {
    const auto c = static_cast<py::ssize_t>(sizeof(float));
    return view(data, im.pixels.data(), {im.height, im.width, im.channels}, {im.width * im.channels * c, im.channels * c, c});
}

// The depth (channel 3 of the hit buffer: negative on misses) and the normals (channels 0..2).
py::array depth_view(const std::shared_ptr<RenderData>& data, const RenderBuffer& b) {
    const auto px = static_cast<py::ssize_t>(sizeof(cl_float4));
    return view(data, &b.hit[0].s[3], {b.height, b.width}, {b.width * px, px});
}

py::array normals_view(const std::shared_ptr<RenderData>& data, const RenderBuffer& b) {
    const auto px = static_cast<py::ssize_t>(sizeof(cl_float4));
    return view(data, &b.hit[0].s[0], {b.height, b.width, 3}, {b.width * px, px, static_cast<py::ssize_t>(sizeof(float))});
}

py::array counters_view(const std::shared_ptr<RenderData>& data, const RenderBuffer& b) {
    const auto px = static_cast<py::ssize_t>(sizeof(cl_uint2));
    return view(data, &b.aux[0].s[0], {b.height, b.width, 2}, {b.width * px, px, static_cast<py::ssize_t>(sizeof(cl_uint))});
}

// The result of Context.render: the report and the arrays.
struct RenderResult {
    py::object report, image, depth, normals, counters;
    py::object reference_image = py::none(), reference_depth = py::none(), difference_image = py::none();
};

// ---- progress ----

// A progress callback for the sweep and the atlas: the user's (with the GIL, given a dict), and a
// check for KeyboardInterrupt between points.
template <class P>
std::function<void(const P&)> progress_function(py::object callback, std::function<py::dict(const P&)> fields) {
    return [callback = std::move(callback), fields = std::move(fields)](const P& p) {
        const py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        if (!callback.is_none()) callback(fields(p));
    };
}

// ---- the context ----

std::string device_spec(const py::object& device) {
    if (device.is_none()) return "";
    if (PyUnicode_Check(device.ptr())) return device.cast<std::string>();
    if (PyLong_Check(device.ptr()) && !PyBool_Check(device.ptr())) return std::to_string(device.cast<long long>());
    if (PyList_Check(device.ptr()) || PyTuple_Check(device.ptr())) {
        std::vector<std::string> items;
        for (const py::handle d : device) items.push_back(device_spec(py::reinterpret_borrow<py::object>(d)));
        return fmt::format("{}", fmt::join(items, ","));
    }
    throw py::type_error(fmt::format("device must be a str, an int or a list of them, got {}", type_name(device)));
}

class Context {
public:
    Context(const py::object& device, const std::optional<std::string>& placement, const py::object& tuning_db,
            bool tuning, const std::optional<std::filesystem::path>& kernel_dir)
        : spec_(device_spec(device)) {
        fault::check();  // a malformed $SDFBRICK_FAULT is refused before any work
        std::optional<pipeline::Placement> p;
        if (placement) {
            p = pipeline::placement_from_string(*placement);
            if (!p) throw SettingError("placement", fmt::format("placement must be whole, replicate or split, got \"{}\"", *placement));
        }
        if (kernel_dir) ocl::set_kernel_dir(*kernel_dir);
        if (tuning) {
            tuning_path_ = tuning_db.is_none() ? tune::TuningDb::default_path()
                                               : std::optional<std::filesystem::path>(
                                                     py::module_::import("os").attr("fspath")(tuning_db).cast<std::string>());
            if (tuning_path_) tuning_db_ = tune::TuningDb::load(*tuning_path_);
        } else if (!tuning_db.is_none()) {
            throw py::type_error("tuning_db is given but tuning is False");
        }
        const py::gil_scoped_release release;
        if (p == pipeline::Placement::split) check_named_once();
        set_ = std::make_unique<ocl::DeviceSet>(ocl::DeviceSet::open(spec_));
        // As the CLI: several devices replicate unless told otherwise; one device alone is whole unless split.
        placement_ = p.value_or(pipeline::Placement::replicate);
        if (placement_ == pipeline::Placement::replicate && set_->size() == 1) placement_ = pipeline::Placement::whole;
        if (placement_ == pipeline::Placement::split) rates_.emplace(pipeline::RateStore::default_path());
        std::vector<ocl::Device*> devices;
        for (ocl::Device& d : *set_) devices.push_back(&d);
        executor_ = std::make_unique<pipeline::Executor>(devices);
    }

    py::list devices() const {
        py::list out;
        for (const ocl::Device& d : open_set()) out.append(to_python(d.info().to_json()));
        return out;
    }
    std::string placement() const { return std::string(pipeline::to_string(placement_)); }
    py::object tuning_db() const { return tuning_path_ ? py::object(py::str(tuning_path_->string())) : py::object(py::none()); }

    void close() {
        const py::gil_scoped_release release;
        const std::lock_guard lock(mutex_);
        executor_.reset();
        set_.reset();
    }

    py::object build(const PyScene& scene, const py::kwargs& kwargs) {
        Kwargs k(kwargs, "build");
        const std::optional<double> time = k.number("time");
        const auto [repeat, warmup] = take_repeats(k);
        const bool reference_levels = k.boolean("reference_levels").value_or(false);
        const BuildArgs args = take_build_settings(k);
        k.done();

        nlohmann::json report_json;
        {
            const py::gil_scoped_release release;
            const std::lock_guard lock(mutex_);
            pipeline::Executor& executor = open_executor();
            const Scene at = scene.at(time);
            pipeline::BuildCommandReport report;
            report.settings = args.settings;
            report.file = scene.file.value_or("");
            report.time = at.time;
            report.scene = at.name;
            report.geometries = at.geometries.size();
            report.repeat = repeat;
            report.warmup = warmup;
            report.tuning_db = tuning_path_;
            pipeline::Job job;
            job.work = pipeline::Work::construct;
            job.settings = tune::settings_for(args.settings, std::nullopt, tuning(), args.given);
            job.warmup = warmup;
            job.repeat = repeat;
            job.image = false;
            job.rates = rates_ ? &*rates_ : nullptr;
            pipeline::add_execution(report, executor.run(at, job, placement_), at, reference_levels);
            report_json = to_json(report);
        }
        return to_python(report_json);
    }

    py::object play(const PyScene& scene, const py::kwargs& kwargs) {
        Kwargs k(kwargs, "play");
        pipeline::PlaySpec spec;
        if (const auto v = k.integer("frames")) spec.frames = *v;
        const std::optional<double> fps = k.number("fps"), dt = k.number("dt"), start = k.number("start");
        const std::optional<std::string> edits = k.string("edits"), work = k.string("work");
        spec.digests = k.boolean("digests").value_or(false);
        const TraceArgs t = take_trace(k);
        BuildArgs args = take_build_settings(k);
        k.done();
        args.given.trace_group = t.group_given;
        args.given.trace_registers = t.registers_given;
        if (fps && dt) throw py::type_error("fps and dt exclude each other");
        if (fps && !(*fps > 0.0)) throw SettingError("fps", fmt::format("fps must be > 0, got {}", *fps));
        if (dt && !(*dt > 0.0)) throw SettingError("dt", fmt::format("dt must be > 0, got {}", *dt));
        spec.dt = dt.value_or(1.0 / fps.value_or(60.0));
        spec.from = start.value_or(scene.scene->time);
        if (work == "construct") spec.work = pipeline::Work::construct;
        else if (work == "bvh") spec.work = pipeline::Work::bvh;
        else if (work && *work != "trace")
            throw SettingError("work", fmt::format("work must be construct, bvh or trace, got \"{}\"", *work));
        if (placement_ == pipeline::Placement::replicate)
            throw InputError("play runs one device, or several with placement split");

        nlohmann::json report_json;
        {
            const py::gil_scoped_release release;
            const std::lock_guard lock(mutex_);
            pipeline::Executor& executor = open_executor();
            std::optional<EditLog> log;
            if (edits) log = load_edit_log(*edits, *scene.scene);
            spec.edits = log ? &*log : nullptr;
            const pipeline::PlayRun run =
                pipeline::play(executor, *scene.scene, tune::settings_for(args.settings, t.trace, tuning(), args.given),
                               placement_, spec);
            const pipeline::PlayRequest request{scene.file.value_or(""), scene.scene->name, t.mode, t.trace,
                                                dt ? 0.0 : 1.0 / spec.dt, "", edits.value_or(""), spec.work};
            report_json = pipeline::to_json(request, run);
        }
        return to_python(report_json);
    }

    RenderResult render(const PyScene& scene, const py::kwargs& kwargs) {
        Kwargs k(kwargs, "render");
        const std::optional<double> time = k.number("time");
        const auto [repeat, warmup] = take_repeats(k);
        pipeline::RenderRequest request;
        request.file = scene.file.value_or("");
        request.repeat = repeat;
        request.warmup = warmup;
        TraceArgs t = take_trace(k);
        request.trace = t.trace;
        request.mode = t.mode;
        render::TraceSettings& trace = request.trace;
        request.compare = k.boolean("compare").value_or(false);
        request.reference = k.boolean("reference").value_or(false);
        BuildArgs args = take_build_settings(k);
        k.done();
        args.given.trace_group = t.group_given;
        args.given.trace_registers = t.registers_given;
        if (request.reference && request.mode != "normals" && request.mode != "depth")
            throw InputError("reference renders the normals and depth modes only");
        if (request.reference && request.compare) throw InputError("reference and compare exclude each other");

        nlohmann::json report_json;
        auto data = std::make_shared<RenderData>();
        {
            const py::gil_scoped_release release;
            const std::lock_guard lock(mutex_);
            pipeline::Executor& executor = open_executor();
            const Scene at = scene.at(time);
            pipeline::Job job;
            job.work = pipeline::Work::trace;
            job.bricks = !request.reference;
            job.brick_digests = false;
            job.reference = request.reference || request.compare;
            job.settings = tune::settings_for(args.settings, trace, tuning(), args.given);
            job.warmup = warmup;
            job.repeat = repeat;
            job.rates = rates_ ? &*rates_ : nullptr;
            pipeline::Execution e = executor.run(at, job, placement_);
            pipeline::RenderCommandReport report = pipeline::render_report(request, at, at.time, args.settings);
            pipeline::RenderImages images = pipeline::add_execution(report, e, at, request);
            data->buffer = std::move(images.buffer);
            data->picture = pipeline::mode_picture(request.mode, data->buffer, images.shaded, false);
            if (request.compare && images.reference) {
                data->reference = std::move(images.reference);
                data->reference_picture =
                    pipeline::mode_picture(request.mode == "depth" ? "depth" : "normals", *data->reference, {}, false);
                data->difference = reference::difference_image(data->buffer, *data->reference,
                                                               report.job ? report.job->figures.voxel_world : 0.0);
            }
            report_json = to_json(report);
        }
        RenderResult r;
        r.report = to_python(report_json);
        r.image = image_view(data, data->picture);
        r.depth = depth_view(data, data->buffer);
        r.normals = normals_view(data, data->buffer);
        r.counters = counters_view(data, data->buffer);
        if (data->reference) {
            r.reference_image = image_view(data, data->reference_picture);
            r.reference_depth = depth_view(data, *data->reference);
            r.difference_image = image_view(data, data->difference);
        }
        return r;
    }

    py::object sweep(const py::object& spec, bool as_frame, const std::optional<std::filesystem::path>& cache,
                     const py::object& progress, const py::kwargs& kwargs) {
        static const char* const kListKeys[] = {"scenes", "brick_sizes", "tolerances", "chunks", "groups", "trace_groups",
                                                "cull", "formats", "samples", "methods", "normals"};
        static const char* const kScalarKeys[] = {"devices", "width", "height", "warmup", "repeat", "accuracy"};
        py::dict d;
        if (!spec.is_none()) {
            if (!PyDict_Check(spec.ptr())) throw py::type_error(fmt::format("sweep(): spec must be a dict, got {}", type_name(spec)));
            for (const auto& [key, value] : py::reinterpret_borrow<py::dict>(spec)) d[key] = value;  // a copy
        }
        for (const auto& [key, value] : kwargs) {
            const std::string name = key.cast<std::string>();
            const bool list = std::find_if(std::begin(kListKeys), std::end(kListKeys), [&](const char* k) { return name == k; }) !=
                              std::end(kListKeys);
            const bool scalar = std::find_if(std::begin(kScalarKeys), std::end(kScalarKeys),
                                             [&](const char* k) { return name == k; }) != std::end(kScalarKeys);
            if (!list && !scalar) throw py::type_error(fmt::format("sweep() got an unexpected keyword argument '{}'", name));
            // A single value of a dimension is a list of one; devices as a Context's device.
            const bool sequence = PyList_Check(value.ptr()) || PyTuple_Check(value.ptr());
            if (name == "devices")
                d[key] = py::str(device_spec(py::reinterpret_borrow<py::object>(value)));
            else
                d[key] = list && !sequence ? py::object(py::make_tuple(value)) : py::reinterpret_borrow<py::object>(value);
        }
        // Scenes given as Scene objects are read from their files.
        if (d.contains("scenes")) {
            py::object scenes = d["scenes"];
            if (PyList_Check(scenes.ptr()) || PyTuple_Check(scenes.ptr())) {
                py::list files;
                std::size_t i = 0;
                for (const py::handle s : scenes) {
                    if (py::isinstance<PyScene>(s)) {
                        const PyScene& scene = s.cast<const PyScene&>();
                        if (!scene.file)
                            throw InputError(fmt::format("<sweep>: /scenes/{}: a scene made in memory has no file; the "
                                                         "sweep reads its scenes from files (save it first)", i));
                        files.append(py::str(*scene.file));
                    } else {
                        files.append(s);
                    }
                    ++i;
                }
                d["scenes"] = files;
            }
        }
        const nlohmann::json j = from_python(d, "<sweep>");
        sweep::SweepSpec s = sweep::spec_from_json(j, "<sweep>");
        if (s.devices.empty()) s.devices = spec_;
        s.validate();
        const auto fn = progress_function<sweep::Progress>(progress, [](const sweep::Progress& p) {
            py::dict f;
            f["done"] = p.done;
            f["total"] = p.total;
            f["cached"] = p.cached;
            f["elapsed_s"] = p.elapsed_s;
            f["eta_s"] = p.eta_s;
            f["current"] = text(p.current);
            return f;
        });
        nlohmann::json rows_json;
        {
            const py::gil_scoped_release release;
            const std::lock_guard lock(mutex_);
            ocl::DeviceSet& context_set = open_set();
            // A sweep that names its devices opens them; else it runs on the context's.
            std::optional<ocl::DeviceSet> own;
            if (s.devices != spec_) own.emplace(ocl::DeviceSet::open(s.devices));
            ocl::DeviceSet& devices = own ? *own : context_set;
            const std::vector<sweep::SweepPoint> points = sweep::expand(s, sweep::device_labels(devices));
            sweep::ResultCache results(cache.value_or(std::filesystem::path()));
            rows_json = sweep::to_json(sweep::run_points(s, points, devices, tuning(), results, fn));
        }
        py::object rows = to_python(rows_json);
        if (!as_frame) return rows;
        return py::module_::import("pandas").attr("DataFrame")(rows);
    }

    py::object stability(const py::object& cases, const py::object& progress, const py::kwargs& kwargs) {
        Kwargs k(kwargs, "stability");
        sweep::StabilitySpec s;
        const double brick_size = k.number("brick_size").value_or(0.125);
        std::vector<std::string> case_texts;
        const auto add_case = [&](py::handle c) {
            if (py::isinstance<PyScene>(c)) {
                const PyScene& scene = c.cast<const PyScene&>();
                if (!scene.file) throw InputError("stability: a scene made in memory has no file; the atlas reads its cases from files");
                case_texts.push_back(*scene.file);
            } else if (PyUnicode_Check(c.ptr()) || py::hasattr(c, "__fspath__")) {
                case_texts.push_back(py::module_::import("os").attr("fspath")(c).cast<std::string>());
            } else {
                throw py::type_error(fmt::format("stability(): cases must be file names or Scene objects, got {}", type_name(c)));
            }
        };
        if (PyList_Check(cases.ptr()) || PyTuple_Check(cases.ptr())) {
            for (const py::handle c : cases) add_case(c);
        } else {
            add_case(cases);
        }
        if (case_texts.empty()) throw InputError("stability: no cases");
        for (const std::string& c : case_texts) s.cases.push_back(sweep::parse_case(c, brick_size));
        if (const auto v = k.strings("methods"))
            for (const std::string& n : *v) {
                const auto m = render::method_from_string(n);
                if (!m) throw SettingError("methods", fmt::format("methods takes {}, got \"{}\"", render::method_names(", "), n));
                s.methods.push_back(*m);
            }
        if (const auto v = k.strings("normals"))
            for (const std::string& n : *v) {
                const auto m = render::normals_from_string(n);
                if (!m) throw SettingError("normals", fmt::format("normals takes central, tetra, continuous, got \"{}\"", n));
                s.normals.push_back(*m);
            }
        if (const auto v = k.strings("formats"))
            for (const std::string& n : *v) {
                const auto f = construct::format_from_string(n);
                if (!f) throw SettingError("formats", fmt::format("formats takes int8, int16, float, got \"{}\"", n));
                s.formats.push_back(*f);
            }
        if (const auto v = k.strings("builds"))
            for (const std::string& n : *v) {
                if (n != "uniform" && n != "adaptive")
                    throw SettingError("builds", fmt::format("builds takes uniform, adaptive, got \"{}\"", n));
                s.adaptive.push_back(n == "adaptive");
            }
        if (const auto v = k.number("tolerance_voxels")) s.tolerance_voxels = *v;
        if (!(s.tolerance_voxels > 0.0)) throw SettingError("tolerance_voxels", "tolerance_voxels must be > 0");
        if (const auto v = k.integer("width")) s.width = *v;
        if (const auto v = k.integer("height")) s.height = *v;
        if (const auto v = k.object("pictures")) s.pictures = py::module_::import("os").attr("fspath")(*v).cast<std::string>();
        k.done();
        if (s.pictures) check_output_folder(*s.pictures);
        const auto fn = progress_function<sweep::StabilityProgress>(progress, [](const sweep::StabilityProgress& p) {
            py::dict f;
            f["done"] = p.done;
            f["total"] = p.total;
            f["elapsed_s"] = p.elapsed_s;
            f["eta_s"] = p.eta_s;
            f["current"] = text(p.current);
            return f;
        });
        nlohmann::json report;
        {
            const py::gil_scoped_release release;
            const std::lock_guard lock(mutex_);
            s.tuning = tuning();
            const sweep::StabilityReport r = sweep::run_stability(s, open_set(), fn);
            sweep::write_stability_outputs(r, s);
            report = sweep::to_json(r);
        }
        return to_python(report);
    }

    py::object tune(const py::object& scene_or_list, const py::object& progress, bool save, const py::kwargs& kwargs) {
        std::vector<PyScene> scenes;
        try {
            if (py::isinstance<py::list>(scene_or_list) || py::isinstance<py::tuple>(scene_or_list))
                scenes = scene_or_list.cast<std::vector<PyScene>>();
            else
                scenes.push_back(scene_or_list.cast<PyScene>());
        } catch (const py::cast_error&) {
            throw SettingError("scenes", "scenes must be a Scene or a list of Scenes");
        }
        if (scenes.empty()) throw SettingError("scenes", "tune needs at least one scene");
        Kwargs k(kwargs, "tune");
        tune::TuneSpec spec;
        std::vector<std::string> names{"evaluate", "trace"};
        if (const auto v = k.strings("kernels")) names = *v;
        if (const auto v = k.string("strategy")) spec.strategy = *v;
        if (const auto v = k.integer("budget")) {
            if (*v < 1) throw SettingError("budget", fmt::format("budget must be at least 1, got {}", *v));
            spec.budget = static_cast<std::size_t>(*v);
        }
        if (const auto v = k.integer("seed")) spec.seed = static_cast<std::uint64_t>(*v);
        if (const auto v = k.integer("repeat")) spec.repeat = *v;
        if (const auto v = k.integer("warmup")) spec.warmup = *v;
        if (spec.repeat < 1 || spec.repeat > 100) throw SettingError("repeat", fmt::format("repeat must lie in 1..100, got {}", spec.repeat));
        if (spec.warmup < 0 || spec.warmup > 100) throw SettingError("warmup", fmt::format("warmup must lie in 0..100, got {}", spec.warmup));
        if (const auto v = k.integer("width")) spec.width = *v;
        if (const auto v = k.integer("height")) spec.height = *v;
        if (const auto v = k.string("method")) spec.method = method_argument(*v);
        const construct::BuildSettings base = take_build_settings(k).settings;
        k.done();
        std::vector<const tune::TunedKernel*> kernels;
        for (const std::string& n : names)
            if (!tune::find_kernel(n)) throw SettingError("kernels", fmt::format("kernels takes evaluate and/or trace, got \"{}\"", n));
        for (const tune::TunedKernel* kernel : tune::tuned_kernels())
            if (std::find(names.begin(), names.end(), kernel->option) != names.end()) kernels.push_back(kernel);
        validate_image_size(spec.width, spec.height);
        if (save && !tuning_path_)
            throw InputError("tune(save=True) writes the tuning database: the context has none (give tuning_db, or "
                             "tuning=True with $SDFBRICK_TUNING_DB not off)");
        // Lines of text as `sdfbrick tune` prints them, to the callback (with the GIL).
        std::function<void(const std::string&)> say;
        tune::TuneProgress measured;
        if (!progress.is_none()) {
            say = [progress](const std::string& line) {
                const py::gil_scoped_acquire gil;
                progress(text(line));
            };
            measured = [say](std::size_t n, const tune::Config& c, double cost, std::span<const double> scene_ms) {
                say(tune::measured_line(n, c, cost, scene_ms));
            };
        }
        const std::string tuned_at =
            py::module_::import("datetime").attr("datetime").attr("now")(py::module_::import("datetime").attr("timezone").attr("utc"))
                .attr("strftime")("%Y-%m-%dT%H:%M:%SZ").cast<std::string>();
        nlohmann::json device_reports = nlohmann::json::array();
        {
            const py::gil_scoped_release release;
            const std::lock_guard lock(mutex_);
            pipeline::Executor& executor = open_executor();
            std::vector<tune::TuneScene> at;
            for (const PyScene& scene : scenes) at.push_back({scene.at(std::nullopt), scene.file.value_or("")});
            for (std::size_t i = 0; i < executor.size(); ++i) base.validate(executor.device(i).info());
            tune::TuningDb db = tuning_db_ ? *tuning_db_ : tune::TuningDb();
            for (std::size_t i = 0; i < executor.size(); ++i)
                device_reports.push_back(
                    tune::tune_device(executor.lane(i), at, kernels, base, spec, db, tuned_at, say, measured));
            if (save) {
                db.save(*tuning_path_);
                tuning_db_ = std::move(db);
            }
        }
        nlohmann::json files = nlohmann::json::array();
        for (const PyScene& scene : scenes) files.push_back(scene.file.value_or(""));
        return to_python({{"command", "tune"},
                          {"scenes", files},
                          {"tuning_db", save ? nlohmann::json(tuning_path_->string()) : nlohmann::json(nullptr)},
                          {"devices", device_reports}});
    }

private:
    const tune::TuningDb* tuning() const { return tuning_db_ ? &*tuning_db_ : nullptr; }

    ocl::DeviceSet& open_set() const {
        if (!set_) throw std::runtime_error("the context is closed");
        return *set_;
    }
    pipeline::Executor& open_executor() {
        if (!executor_) throw std::runtime_error("the context is closed");
        return *executor_;
    }

    // A split uses each device once: a device named twice is refused.
    void check_named_once() const {
        const std::vector<ocl::DeviceInfo> all = ocl::list_devices();
        std::vector<std::size_t> seen;
        std::string_view spec = spec_;
        while (!spec.empty()) {
            const std::size_t comma = spec.find(',');
            for (std::size_t i : ocl::select_devices(spec.substr(0, comma), all)) {
                if (std::find(seen.begin(), seen.end(), i) != seen.end())
                    throw SettingError("device", fmt::format("device {} ({}) is named twice; a split run uses each device once",
                                                             i, all[i].name));
                seen.push_back(i);
            }
            spec = comma == std::string_view::npos ? std::string_view{} : spec.substr(comma + 1);
        }
    }

    std::string spec_;
    std::unique_ptr<ocl::DeviceSet> set_;
    pipeline::Placement placement_ = pipeline::Placement::whole;
    std::optional<pipeline::RateStore> rates_;
    std::unique_ptr<pipeline::Executor> executor_;
    std::optional<std::filesystem::path> tuning_path_;
    std::optional<tune::TuningDb> tuning_db_;
    std::mutex mutex_;  // one call at a time on the devices (taken with the GIL released)
};

py::list devices(const py::object& device) {
    const std::vector<ocl::DeviceInfo> all = ocl::list_devices();
    const std::vector<std::size_t> selected = ocl::select_devices(device_spec(device), all);
    py::list out;
    for (const ocl::DeviceInfo& d : all) {
        nlohmann::json j = d.to_json();
        j["selected"] = std::find(selected.begin(), selected.end(), d.index) != selected.end();
        out.append(to_python(j));
    }
    return out;
}

void bind_scene(py::module_& m) {
    py::class_<PyScene>(m, "Scene", "A scene: objects that instance geometries, each an ordered list of CSG edits.")
        .def_static("load", &PyScene::load, py::arg("path"), "Reads a scene file (JSON, docs/scene-format.md).")
        .def_static("from_dict", &PyScene::from_dict, py::arg("d"), py::arg("base") = py::none(),
                    "A scene from a dict in the scene file format; base: the folder mesh files are read from.")
        .def_static("from_json", &PyScene::from_json, py::arg("text"), py::arg("base") = py::none(),
                    "A scene from the text of a scene file.")
        .def_static(
            "generate", [](const std::string& name, std::uint64_t seed) { return PyScene{std::make_shared<const Scene>(generate_scene(name, seed)), {}}; },
            py::arg("name"), py::arg("seed") = kDefaultSceneSeed, "A generated scene (the names of `sdfbrick scene generate`).")
        .def("to_dict", [](const PyScene& s) { return to_python(scene_to_json(*s.scene)); })
        .def("to_json", [](const PyScene& s) { return format_scene(*s.scene); }, "The text of the scene file.")
        .def("save", [](const PyScene& s, const std::filesystem::path& path) { save_scene(*s.scene, path); }, py::arg("path"))
        .def(
            "info",
            [](const PyScene& s, std::optional<double> time) {
                Scene scene = *s.scene;
                if (time) scene.time = *time;
                SceneSummary summary = scene_summary(scene);
                summary.file = s.file.value_or("");
                return to_python(to_json(summary));
            },
            py::arg("time") = py::none(), "What `sdfbrick scene info --json` reports: edits, histograms, bounds, camera.")
        .def_property_readonly("name", [](const PyScene& s) { return s.scene->name; })
        .def_property_readonly("time", [](const PyScene& s) { return s.scene->time; })
        .def_property_readonly("file", [](const PyScene& s) { return s.file; })
        .def_property_readonly("warnings", [](const PyScene& s) { return s.scene->warnings; },
                               "What reading the file changed, one line each (a mesh's winding turned).")
        .def("__repr__", [](const PyScene& s) {
            return fmt::format("<sdfbrick.Scene {} ({} geometries, {} objects{})>", quoted_input(s.scene->name),
                               s.scene->geometries.size(), s.scene->objects.size(), s.file ? ", from " + *s.file : "");
        });
}

void bind_render_result(py::module_& m) {
    py::class_<RenderResult>(m, "RenderResult", "What Context.render gives: the report and the pictures as arrays.")
        .def_readonly("report", &RenderResult::report, "The report (the schema of `sdfbrick render --json`).")
        .def_readonly("image", &RenderResult::image, "The picture of the mode, float32 H x W x 3 (a view, no copy).")
        .def_readonly("depth", &RenderResult::depth, "Depth along the ray, float32 H x W; negative on misses (a view).")
        .def_readonly("normals", &RenderResult::normals, "World normals, float32 H x W x 3; 0 on misses (a view).")
        .def_readonly("counters", &RenderResult::counters, "Per pixel brick id and step counters, uint32 H x W x 2 (a view).")
        .def_readonly("reference_image", &RenderResult::reference_image, "compare=True: the reference's picture.")
        .def_readonly("reference_depth", &RenderResult::reference_depth, "compare=True: the reference's depth.")
        .def_readonly("difference_image", &RenderResult::difference_image, "compare=True: the difference picture.")
        .def_property_readonly("accuracy", [](const RenderResult& r) { return r.report.attr("get")("accuracy"); },
                               "compare=True: the accuracy figures against the reference (report[\"accuracy\"]).");
}

void bind_context(py::module_& m) {
    py::class_<Context>(m, "Context",
                        "Opened devices and an executor over them; its lanes keep their programs, memory and image "
                        "buffers from call to call. One call at a time runs on the devices.")
        .def(py::init<const py::object&, const std::optional<std::string>&, const py::object&, bool,
                      const std::optional<std::filesystem::path>&>(),
             py::arg("device") = py::none(), py::arg("placement") = py::none(), py::arg("tuning_db") = py::none(),
             py::arg("tuning") = true, py::arg("kernel_dir") = py::none(),
             "device: a spec as the CLI's --device (an index, gpu, cpu, all, part of a name; comma-separated) or a list "
             "of them; placement: whole, replicate or split (default: replicate, whole with one device); tuning_db: the "
             "tuning database file (default: the CLI's); tuning=False ignores it.")
        .def_property_readonly("devices", &Context::devices)
        .def_property_readonly("placement", &Context::placement)
        .def_property_readonly("tuning_db", &Context::tuning_db)
        .def("close", &Context::close, "Releases the devices; later calls raise.")
        .def("__enter__", [](py::object self) { return self; })
        .def("__exit__", [](Context& c, const py::args&) { c.close(); })
        .def("build", &Context::build, py::arg("scene"),
             "Builds the scene's bricks: keyword arguments as the report's settings (brick_size, levels, branching, "
             "samples, format, band_voxels, guard, chunk, group, eval_max_registers, lanes, count_parts, count_splits, "
             "count_untested, cull, cull_siblings, skip_far, apron_share_edits, dependencies, tolerance, max_brick_size) "
             "and tolerance_voxels, time, repeat, warmup, reference_levels. Returns the report (the schema of "
             "`sdfbrick build --json`).")
        .def("play", &Context::play, py::arg("scene"),
             "Plays the scene's animation (and an edit log: edits=PATH) frame by frame: the report of "
             "`sdfbrick play --json` (frames=, fps= or dt=, start=, work=, digests=, the render and build keywords)")
        .def("render", &Context::render, py::arg("scene"),
             "Builds and traces the scene: the build's keyword arguments and width, height, mode, method, normals, "
             "compare, reference, group_x, group_y, shadow_rays, ao_rays, max_registers. Returns a RenderResult.")
        .def("sweep", &Context::sweep, py::arg("spec") = py::none(), py::kw_only(), py::arg("as_frame") = false,
             py::arg("cache") = py::none(), py::arg("progress") = py::none(),
             "Runs a sweep: spec is a dict of sweep-file keys (docs/sweep.md), keyword arguments add to it. Returns the "
             "rows (a pandas DataFrame with as_frame=True). cache: a resume file (default: none); progress: called with "
             "a dict before each point.")
        .def("stability", &Context::stability, py::arg("cases"), py::kw_only(), py::arg("progress") = py::none(),
             "The stability atlas over cases (files, FILE@BRICK_SIZE or Scene objects from files): brick_size, methods, "
             "normals, formats, builds, tolerance_voxels, width, height, pictures. Returns the report.")
        .def("tune", &Context::tune, py::arg("scenes"), py::kw_only(), py::arg("progress") = py::none(),
             py::arg("save") = false,
             "Tunes the evaluation and trace kernels on every device of the context over a Scene or a list of them (with "
             "several, a configuration's cost is the geometric mean of its times on each; kernels, strategy, budget, seed, "
             "repeat, warmup, width, height, and the build's keyword arguments). Returns the report of `sdfbrick tune "
             "--json`; save=True also writes the winners to the context's tuning database, which later calls use. "
             "progress: called with each line `sdfbrick tune` prints.");
}

}  // namespace

}  // namespace sdfbrick::python

PYBIND11_MODULE(sdfbrick, m) {
    using namespace sdfbrick;
    using namespace sdfbrick::python;
    m.doc() = "sdfbrick: sparse signed-distance-field bricks from CSG edit lists, on any OpenCL device";
    m.attr("__version__") = SDFBRICK_VERSION;

    static py::exception<InputError> input(m, "InputError", PyExc_ValueError);
    static py::exception<ocl::ClError> device(m, "DeviceError", PyExc_RuntimeError);
    input.doc() = "Bad input: a scene, a setting, a device name. The message is the CLI's one line.";
    device.doc() = "A device failure (an OpenCL error). The message is the CLI's one line.";
    input_error = input.ptr();
    device_error = device.ptr();
    py::register_exception_translator(translate);

    m.def("devices", &devices, py::arg("device") = py::none(),
          "Every OpenCL device as a dict (the fields of `sdfbrick devices --json`); \"selected\" marks those the "
          "device spec selects (None: $SDFBRICK_DEVICE, else the default).");

    bind_scene(m);
    bind_render_result(m);
    bind_context(m);
}
