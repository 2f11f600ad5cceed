#include "cl/digest.h"

#include <algorithm>
#include <stdexcept>

#include "cl/cl_error.h"
#include "cl/launch.h"
#include "core/hash.h"

namespace sdfbrick::ocl {

namespace {

constexpr std::size_t kGroup = 64;

std::size_t round_up(std::size_t n, std::size_t m) { return (n + m - 1) / m * m; }

bool little_endian(const Device& d) {
    cl_bool little = CL_FALSE;
    check(clGetDeviceInfo(d.id(), CL_DEVICE_ENDIAN_LITTLE, sizeof(little), &little, nullptr),
          "querying CL_DEVICE_ENDIAN_LITTLE");
    return little == CL_TRUE;
}

}  // namespace

DeviceDigest::DeviceDigest(Device& device)
    : device_(device), program_(build_program(device, "digest.cl")), blocks_(make_kernel(program_, "digest_blocks")),
      lists_(make_kernel(program_, "digest_lists")) {
    if (!little_endian(device))
        throw ClError(CL_INVALID_DEVICE, "digests assume a little-endian device; " + device.info().name + " is not");
}

DeviceDigest::~DeviceDigest() = default;

std::size_t DeviceDigest::block_bytes(std::size_t take) {
    return std::max<std::size_t>(1, kTreeDigestBlock / std::max<std::size_t>(take, 1)) * std::max<std::size_t>(take, 1);
}

Buffer<cl_ulong>& DeviceDigest::scratch(int i, std::size_t count) {
    auto& s = scratch_[i];
    if (!s || s->size() < count) s = std::make_unique<Buffer<cl_ulong>>(device_, std::max<std::size_t>(count, 1));
    return *s;
}

std::size_t DeviceDigest::slot(const Buffer<cl_ulong>& from) {
    if (!results_ || results_->size() <= slots_) {  // grow: the slots so far are copied in queue order
        auto bigger = std::make_unique<Buffer<cl_ulong>>(device_, std::max<std::size_t>(16, 2 * slots_ + 2));
        if (results_ && slots_ > 0)
            check(clEnqueueCopyBuffer(device_.queue(), results_->get(), bigger->get(), 0, 0, slots_ * sizeof(cl_ulong), 0,
                                      nullptr, nullptr),
                  "copying digest slots");
        results_ = std::move(bigger);
    }
    check(clEnqueueCopyBuffer(device_.queue(), from.get(), results_->get(), 0, slots_ * sizeof(cl_ulong),
                              sizeof(cl_ulong), 0, nullptr, nullptr),
          "copying a digest into its slot");
    return slots_++;
}

std::size_t DeviceDigest::reduce(std::size_t blocks) {
    constexpr std::size_t kPer = kTreeDigestBlock / sizeof(cl_ulong);
    int from = 0;
    while (blocks > 1) {
        const std::size_t next = (blocks + kPer - 1) / kPer;
        Buffer<cl_ulong>& out = scratch(1 - from, next);
        set_args(blocks_.get(), *scratch_[from], static_cast<cl_ulong>(blocks), cl_uint{8}, cl_uint{0}, cl_uint{8},
                 static_cast<cl_uint>(kPer), out);
        enqueue_kernel(next);
        from = 1 - from;
        blocks = next;
    }
    return slot(*scratch_[from]);
}

std::vector<std::uint64_t> DeviceDigest::read_all() {
    std::vector<std::uint64_t> values(slots_);
    if (slots_ > 0) results_->read_into(std::span(values.data(), slots_));
    slots_ = 0;
    return values;
}

std::uint64_t DeviceDigest::digest(cl_mem data, const Records& w) {
    if (slots_ > 0) throw std::logic_error("DeviceDigest::digest with a batch pending");
    enqueue(data, w);
    return read_all().front();
}

std::uint64_t DeviceDigest::leaf_lists(const Buffer<SdfBrick>& leaves, const Buffer<cl_uint>& lists) {
    if (slots_ > 0) throw std::logic_error("DeviceDigest::leaf_lists with a batch pending");
    enqueue_leaf_lists(leaves, lists);
    return read_all().front();
}

std::size_t DeviceDigest::enqueue(cl_mem data, const Records& w) {
    if (w.first + w.take > w.stride) throw std::invalid_argument("DeviceDigest: a record's bytes lie outside its stride");
    if (w.records == 0 || w.take == 0) {  // the empty stream: FNV-1a 64's basis
        Buffer<cl_ulong>& basis = scratch(0, 1);
        const cl_ulong value = Fnv1a64().value();
        check(clEnqueueFillBuffer(device_.queue(), basis.get(), &value, sizeof(value), 0, sizeof(value), 0, nullptr,
                                  nullptr),
              "writing the empty digest");
        return slot(basis);
    }
    const std::size_t per_block = block_bytes(w.take) / w.take;
    const std::size_t blocks = (w.records + per_block - 1) / per_block;
    set_args(blocks_.get(), data, static_cast<cl_ulong>(w.records), static_cast<cl_uint>(w.stride),
             static_cast<cl_uint>(w.first), static_cast<cl_uint>(w.take), static_cast<cl_uint>(per_block),
             scratch(0, blocks));
    enqueue_kernel(blocks);
    return reduce(blocks);
}

std::size_t DeviceDigest::enqueue_leaf_lists(const Buffer<SdfBrick>& leaves, const Buffer<cl_uint>& lists) {
    Buffer<cl_ulong>& per_leaf = scratch(2, leaves.size());
    if (leaves.size() > 0) {
        set_args(lists_.get(), leaves, static_cast<cl_uint>(leaves.size()), lists, per_leaf);
        ocl::enqueue(device_, lists_.get(), "digest_lists", round_up(leaves.size(), kGroup), kGroup);
    }
    return enqueue(per_leaf.get(), {leaves.size(), 8, 0, 8});
}

void DeviceDigest::enqueue_kernel(std::size_t items) {
    ocl::enqueue(device_, blocks_.get(), "digest_blocks", round_up(items, kGroup), kGroup);
}

}  // namespace sdfbrick::ocl
