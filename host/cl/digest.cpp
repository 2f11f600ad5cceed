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

std::uint64_t DeviceDigest::reduce(std::size_t blocks) {
    constexpr std::size_t kPer = kTreeDigestBlock / sizeof(cl_ulong);
    int from = 0;
    while (blocks > 1) {
        const std::size_t next = (blocks + kPer - 1) / kPer;
        Buffer<cl_ulong>& out = scratch(1 - from, next);
        set_args(blocks_.get(), *scratch_[from], static_cast<cl_ulong>(blocks), cl_uint{8}, cl_uint{0}, cl_uint{8},
                 static_cast<cl_uint>(kPer), out);
        enqueue(device_, blocks_.get(), "digest_blocks", round_up(next, kGroup), kGroup);
        from = 1 - from;
        blocks = next;
    }
    cl_ulong value = 0;
    scratch_[from]->read_into(std::span(&value, 1));
    return value;
}

std::uint64_t DeviceDigest::digest(cl_mem data, const Records& w) {
    if (w.records == 0 || w.take == 0) return Fnv1a64().value();
    if (w.first + w.take > w.stride) throw std::invalid_argument("DeviceDigest: a record's bytes lie outside its stride");
    const std::size_t per_block = block_bytes(w.take) / w.take;
    const std::size_t blocks = (w.records + per_block - 1) / per_block;
    Buffer<cl_ulong>& out = scratch(0, blocks);
    const cl_ulong records = w.records;
    const cl_uint stride = static_cast<cl_uint>(w.stride), first = static_cast<cl_uint>(w.first),
                  take = static_cast<cl_uint>(w.take), per = static_cast<cl_uint>(per_block);
    const cl_mem out_mem = out.get();
    cl_kernel k = blocks_.get();
    detail::set_kernel_arg(k, 0, sizeof(cl_mem), &data, "buffer");
    detail::set_kernel_arg(k, 1, sizeof(records), &records, "scalar");
    detail::set_kernel_arg(k, 2, sizeof(stride), &stride, "scalar");
    detail::set_kernel_arg(k, 3, sizeof(first), &first, "scalar");
    detail::set_kernel_arg(k, 4, sizeof(take), &take, "scalar");
    detail::set_kernel_arg(k, 5, sizeof(per), &per, "scalar");
    detail::set_kernel_arg(k, 6, sizeof(cl_mem), &out_mem, "buffer");
    enqueue(device_, k, "digest_blocks", round_up(blocks, kGroup), kGroup);
    return reduce(blocks);
}

std::uint64_t DeviceDigest::leaf_lists(const Buffer<SdfBrick>& leaves, const Buffer<cl_uint>& lists) {
    Buffer<cl_ulong>& per_leaf = scratch(2, leaves.size());
    if (leaves.size() > 0) {
        set_args(lists_.get(), leaves, static_cast<cl_uint>(leaves.size()), lists, per_leaf);
        enqueue(device_, lists_.get(), "digest_lists", round_up(leaves.size(), kGroup), kGroup);
    }
    return digest(per_leaf.get(), {leaves.size(), 8, 0, 8});
}

}  // namespace sdfbrick::ocl
