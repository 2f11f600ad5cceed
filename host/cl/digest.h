// Tree digests (core/hash.h: tree_digest) of what stays on a device, computed there: one small
// value crosses to the host, never the buffer. The result equals tree_digest of the same bytes on
// the host (tests/cl). A DeviceDigest keeps its program and its scratch (grown, never shrunk) for
// the digests of a run.
#pragma once

#include <CL/cl.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "cl/buffer.h"
#include "cl/device.h"
#include "cl/program.h"
#include "sdf_types.h"

namespace sdfbrick::ocl {

// Which bytes of a buffer form the stream: for each of `records` records of `stride` bytes, bytes
// [first, first + take). A plain byte array is {bytes, 1, 0, 1}.
struct Records {
    std::size_t records = 0;
    std::size_t stride = 1, first = 0, take = 1;
};

class DeviceDigest {
public:
    // Throws ClError when the device is not little-endian (the digests' byte order).
    explicit DeviceDigest(Device& device);
    ~DeviceDigest();
    Device& device() { return device_; }

    // tree_digest of the selected bytes of data (a buffer of this device), in blocks of whole records
    // (kTreeDigestBlock / take of them, at least one): the host twin is tree_digest(stream,
    // block_bytes(take)). Waits for the one value.
    std::uint64_t digest(cl_mem data, const Records& what);
    template <class T>
    std::uint64_t bytes(const Buffer<T>& b) {
        return digest(b.get(), {b.bytes(), 1, 0, 1});
    }
    // tree_digest of the per-leaf FNV-1a 64 of each leaf's coordinate and edit list (little-endian
    // 8-byte values): the edit-list digest of a build.
    std::uint64_t leaf_lists(const Buffer<SdfBrick>& leaves, const Buffer<cl_uint>& lists);

    // The same, batched: each enqueue_* call only enqueues (the queue is in order) and returns its
    // slot; read_all() waits once and returns every slot's value since the last read_all.
    std::size_t enqueue(cl_mem data, const Records& what);
    std::size_t enqueue_leaf_lists(const Buffer<SdfBrick>& leaves, const Buffer<cl_uint>& lists);
    std::vector<std::uint64_t> read_all();

    static std::size_t block_bytes(std::size_t take);

private:
    std::size_t reduce(std::size_t blocks);  // the level digests in scratch_[0] down to one value, into a slot
    std::size_t slot(const Buffer<cl_ulong>& from);  // copies from[0] into the next result slot
    Buffer<cl_ulong>& scratch(int i, std::size_t count);
    void enqueue_kernel(std::size_t items);  // digest_blocks over items blocks, arguments set
    Device& device_;
    Program program_;
    Kernel blocks_, lists_;
    std::unique_ptr<Buffer<cl_ulong>> scratch_[3];  // two for the levels, one for per-leaf values
    std::unique_ptr<Buffer<cl_ulong>> results_;     // the slots of the batch
    std::size_t slots_ = 0;
};

}  // namespace sdfbrick::ocl
