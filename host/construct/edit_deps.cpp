#include "construct/edit_deps.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "cl/launch.h"

namespace sdfbrick::construct {

namespace {

constexpr measure::Stage kBoundsStage = measure::Stage::edit_bounds;
constexpr measure::Stage kDepsStage = measure::Stage::dependencies;

// Cells per axis never exceed this (the cell count is bounded by the box count anyway).
constexpr double kMaxDim = double(1u << 20);

struct Grid {
    std::array<float, 3> origin{0.0f, 0.0f, 0.0f};
    float inv = 0.0f;  // 1 / cell side; 0: a single cell
    std::array<std::uint32_t, 3> dims{1, 1, 1};
    double cell = 0.0;

    std::uint64_t cells() const { return std::uint64_t{dims[0]} * dims[1] * dims[2]; }
};

// Union of the finite coordinates of the valid influence boxes, their mean extent, their count.
struct BoxStats {
    std::array<double, 3> lo{}, hi{}, mean_extent{};
    std::size_t boxes = 0;
    bool usable() const {
        for (int a = 0; a < 3; ++a)
            if (!std::isfinite(lo[a]) || !std::isfinite(hi[a]) || lo[a] > hi[a]) return false;
        return true;
    }
};

std::uint64_t cells_for(const std::array<double, 3>& extent, double cell) {
    std::uint64_t cells = 1;
    for (double e : extent) cells *= static_cast<std::uint64_t>(std::clamp(std::ceil(e / cell), 1.0, kMaxDim));
    return cells;
}

Grid single_cell() { return Grid{}; }

Grid grid_with_cell(const BoxStats& s, double cell) {
    const double inv = 1.0 / cell;
    if (!(cell > 0.0) || !std::isfinite(cell) || !(inv > 0.0) ||
        !(inv < double(std::numeric_limits<float>::max())) || static_cast<float>(inv) <= 0.0f)
        return single_cell();
    Grid g;
    g.cell = cell;
    g.inv = static_cast<float>(inv);
    for (int a = 0; a < 3; ++a) {
        g.origin[a] = static_cast<float>(s.lo[a]);
        g.dims[a] = static_cast<std::uint32_t>(std::clamp(std::ceil((s.hi[a] - s.lo[a]) / cell), 1.0, kMaxDim));
    }
    if (g.cells() == 1) return single_cell();
    return g;
}

// About one cell per box (the smallest cubic cell for which the grid over the union has at most as
// many cells as there are boxes), but no smaller than the mean box extent (averaged over the axes),
// so that a typical box covers at most 2 x 2 x 2 cells.
Grid choose_grid(const BoxStats& s) {
    if (s.boxes < 2 || !s.usable()) return single_cell();
    const std::array<double, 3> extent{s.hi[0] - s.lo[0], s.hi[1] - s.lo[1], s.hi[2] - s.lo[2]};
    const double widest = std::max({extent[0], extent[1], extent[2]});
    if (!(widest > 0.0)) return single_cell();
    const auto target = static_cast<std::uint64_t>(s.boxes);
    // cells_for is non-increasing in the cell side: bisect (geometrically) for the smallest fitting side.
    double hi = widest;  // one cell along the widest axis: fits
    double lo = widest / kMaxDim;
    if (cells_for(extent, lo) <= target) {
        hi = lo;
    } else {
        for (int it = 0; it < 64 && hi / lo > 1.0 + 1e-6; ++it) {
            const double mid = std::sqrt(lo * hi);
            (cells_for(extent, mid) <= target ? hi : lo) = mid;
        }
    }
    const double mean = (s.mean_extent[0] + s.mean_extent[1] + s.mean_extent[2]) / 3.0;
    double cell = hi;
    if (std::isfinite(mean) && mean > cell) cell = mean;
    return grid_with_cell(s, cell);
}

}  // namespace

std::size_t EditDependencies::bytes() const {
    return bounds.bytes() + influence.bytes() + offsets.bytes() + indices.bytes();
}

std::size_t DependencyBuilder::max_refs(std::size_t n) { return std::max<std::size_t>(32 * n, 65536); }

DependencyBuilder::DependencyBuilder(ocl::Device& device, Scan& scan)
    : device_(device), scan_(scan), bounds_program_(ocl::build_program(device, "edit_bounds.cl")),
      deps_program_(ocl::build_program(device, "edit_deps.cl")),
      edit_bounds_(ocl::make_kernel(bounds_program_, "edit_bounds")),
      grid_stats_(ocl::make_kernel(deps_program_, "grid_stats")),
      grid_refs_(ocl::make_kernel(deps_program_, "grid_refs")),
      fill_uint_(ocl::make_kernel(deps_program_, "fill_uint")),
      grid_count_(ocl::make_kernel(deps_program_, "grid_count")),
      grid_fill_(ocl::make_kernel(deps_program_, "grid_fill")),
      grid_sort_(ocl::make_kernel(deps_program_, "grid_sort")),
      deps_count_(ocl::make_kernel(deps_program_, "deps_count")),
      deps_write_(ocl::make_kernel(deps_program_, "deps_write")) {
    const std::size_t limit = std::min(ocl::kernel_work_group_limit(device, grid_stats_.get(), "grid_stats"),
                                       ocl::kernel_work_group_limit(device, grid_refs_.get(), "grid_refs"));
    while (reduce_local_ > 1 && reduce_local_ > limit) reduce_local_ /= 2;  // stays a power of two
}

// One compute() call: the edits, the output and the scratch memory it tracks, and its steps.
class DependencyBuilder::Job {
public:
    Job(DependencyBuilder& b, const ocl::Buffer<SdfEdit>& edits, std::size_t count, measure::Scheduler& scheduler,
        EditDependencies& out)
        : b_(b), edits_(edits), count_(count), n_(static_cast<cl_uint>(count)), scheduler_(scheduler), out_(out),
          groups_((count + b.reduce_local_ - 1) / b.reduce_local_), reduce_global_(groups_ * b.reduce_local_) {}

    void bounds() {
        ocl::set_args(b_.edit_bounds_.get(), edits_, n_, out_.bounds, out_.influence);
        scheduler_.launch(kBoundsStage, -1, b_.edit_bounds_.get(), count_);
    }

    // Union, mean extent and count of the influence boxes (a small read-back: 10 floats per work-group).
    BoxStats box_stats() {
        ocl::Buffer<float> partials(b_.device_, groups_ * 10);
        hold(partials.bytes());
        ocl::set_args(b_.grid_stats_.get(), out_.influence, n_, partials,
                      ocl::LocalMemory{10 * b_.reduce_local_ * sizeof(float)});
        scheduler_.launch(kDepsStage, -1, b_.grid_stats_.get(), reduce_global_, b_.reduce_local_);
        const std::vector<float> p = partials.read();
        release(partials.bytes());
        BoxStats stats;
        std::array<double, 3> sum{0.0, 0.0, 0.0};
        for (int a = 0; a < 3; ++a) {
            stats.lo[a] = std::numeric_limits<double>::infinity();
            stats.hi[a] = -std::numeric_limits<double>::infinity();
        }
        double boxes = 0.0;
        for (std::size_t g = 0; g < groups_; ++g) {
            for (int a = 0; a < 3; ++a) {
                stats.lo[a] = std::min(stats.lo[a], double(p[g * 10 + a]));
                stats.hi[a] = std::max(stats.hi[a], double(p[g * 10 + 3 + a]));
                sum[a] += double(p[g * 10 + 6 + a]);
            }
            boxes += double(p[g * 10 + 9]);
        }
        stats.boxes = static_cast<std::size_t>(boxes);
        for (int a = 0; a < 3; ++a) stats.mean_extent[a] = boxes > 0.0 ? sum[a] / boxes : 0.0;
        return stats;
    }

    // choose_grid's grid, coarsened until its cell references fit max_refs.
    Grid fit_grid(const BoxStats& stats) {
        Grid grid = choose_grid(stats);
        const std::uint64_t cap = max_refs(count_);
        ocl::Buffer<cl_ulong> partials(b_.device_, groups_);
        hold(partials.bytes());
        for (int attempt = 0; grid.cells() != 1; ++attempt) {
            set_grid_args(b_.grid_refs_.get(), grid, partials, ocl::LocalMemory{b_.reduce_local_ * sizeof(cl_ulong)});
            scheduler_.launch(kDepsStage, -1, b_.grid_refs_.get(), reduce_global_, b_.reduce_local_);
            std::uint64_t refs = 0;
            for (cl_ulong r : partials.read()) refs += r;
            if (refs <= cap) break;
            if (attempt >= 24) {
                grid = single_cell();
                continue;
            }
            const double factor = std::max(1.25, std::cbrt(double(refs) / double(cap)));
            grid = grid_with_cell(stats, grid.cell * factor);
        }
        release(partials.bytes());
        return grid;
    }

    // The boxes of every grid cell (starts, items), then every edit's dependency list.
    void lists(const Grid& grid) {
        const std::size_t cells = static_cast<std::size_t>(grid.cells());
        ocl::Buffer<cl_uint> cell_counts(b_.device_, cells + 1);  // + 1: a 0 whose exclusive scan is the total
        ocl::Buffer<cl_uint> cell_starts(b_.device_, cells + 1);
        hold(cell_counts.bytes() + cell_starts.bytes());
        ocl::set_args(b_.fill_uint_.get(), cell_counts, static_cast<cl_uint>(cells + 1), cl_uint{0});
        scheduler_.launch(kDepsStage, -1, b_.fill_uint_.get(), cells + 1);
        set_grid_args(b_.grid_count_.get(), grid, cell_counts);
        scheduler_.launch(kDepsStage, -1, b_.grid_count_.get(), count_);
        const std::uint64_t total_refs =
            b_.scan_.exclusive(cell_counts, cell_starts, cells + 1, scheduler_, kDepsStage, -1);
        ocl::Buffer<cl_uint> items(b_.device_, static_cast<std::size_t>(total_refs));
        hold(items.bytes());
        set_grid_args(b_.grid_fill_.get(), grid, cell_starts, cell_counts, items);
        scheduler_.launch(kDepsStage, -1, b_.grid_fill_.get(), count_);
        ocl::set_args(b_.grid_sort_.get(), cell_starts, static_cast<cl_uint>(cells), items);
        scheduler_.launch(kDepsStage, -1, b_.grid_sort_.get(), cells);
        dependency_lists(grid, cell_starts, items);
        out_.scratch_bytes = peak_;
        out_.grid_dims = grid.dims;
        out_.grid_cell = grid.inv > 0.0f ? static_cast<float>(grid.cell) : 0.0f;
        out_.grid_refs = static_cast<std::size_t>(total_refs);
    }

private:
    void dependency_lists(const Grid& grid, const ocl::Buffer<cl_uint>& cell_starts, const ocl::Buffer<cl_uint>& items) {
        ocl::set_args(b_.deps_count_.get(), edits_, out_.influence, n_, grid.origin[0], grid.origin[1], grid.origin[2],
                      grid.inv, grid.dims[0], grid.dims[1], grid.dims[2], cell_starts, items, out_.offsets);
        scheduler_.launch(kDepsStage, -1, b_.deps_count_.get(), count_ + 1);
        out_.total = static_cast<std::size_t>(
            b_.scan_.exclusive(out_.offsets, out_.offsets, count_ + 1, scheduler_, kDepsStage, -1));
        out_.indices = ocl::Buffer<cl_uint>(b_.device_, out_.total);
        if (out_.total == 0) return;
        ocl::set_args(b_.deps_write_.get(), edits_, out_.influence, n_, grid.origin[0], grid.origin[1], grid.origin[2],
                      grid.inv, grid.dims[0], grid.dims[1], grid.dims[2], cell_starts, items, out_.offsets,
                      out_.indices);
        scheduler_.launch(kDepsStage, -1, b_.deps_write_.get(), count_);
    }

    template <class... Rest>
    void set_grid_args(cl_kernel k, const Grid& grid, Rest&&... rest) {
        ocl::set_args(k, out_.influence, n_, grid.origin[0], grid.origin[1], grid.origin[2], grid.inv, grid.dims[0],
                      grid.dims[1], grid.dims[2], std::forward<Rest>(rest)...);
    }
    void hold(std::size_t bytes) {
        scratch_ += bytes;
        peak_ = std::max(peak_, scratch_);
    }
    void release(std::size_t bytes) { scratch_ -= bytes; }

    DependencyBuilder& b_;
    const ocl::Buffer<SdfEdit>& edits_;
    std::size_t count_;
    cl_uint n_;
    measure::Scheduler& scheduler_;
    EditDependencies& out_;
    std::size_t groups_, reduce_global_;
    std::size_t scratch_ = 0, peak_ = 0;
};

EditDependencies DependencyBuilder::compute(const ocl::Buffer<SdfEdit>& edits, std::size_t count,
                                            measure::Scheduler& scheduler) {
    if (count > edits.size())
        throw std::out_of_range(fmt::format("DependencyBuilder::compute: {} edits asked for, the buffer holds {}",
                                            count, edits.size()));
    if (count >= 0xffffffffu)
        throw std::length_error(fmt::format("DependencyBuilder::compute: {} edits is too many", count));
    EditDependencies out{ocl::Buffer<SdfBounds>(device_, count), ocl::Buffer<SdfBounds>(device_, count),
                         ocl::Buffer<cl_uint>(device_, count + 1), ocl::Buffer<cl_uint>(device_, 0)};
    if (count == 0) {
        const std::array<cl_uint, 1> zero{0};
        out.offsets.write(zero);
        return out;
    }
    Job job(*this, edits, count, scheduler, out);
    job.bounds();
    job.lists(job.fit_grid(job.box_stats()));
    return out;
}

}  // namespace sdfbrick::construct
