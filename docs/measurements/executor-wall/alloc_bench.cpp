// Times buffer allocation against reuse on the first GPU: create + fill + finish + release vs fill + finish.
#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>
#include <chrono>
#include <cstdio>
#include <vector>
int main() {
    cl_uint np = 0; clGetPlatformIDs(0, nullptr, &np); std::vector<cl_platform_id> ps(np); clGetPlatformIDs(np, ps.data(), nullptr);
    for (cl_platform_id p : ps) {
        cl_device_id d; cl_uint nd = 0;
        if (clGetDeviceIDs(p, CL_DEVICE_TYPE_ALL, 1, &d, &nd) != CL_SUCCESS || nd == 0) continue;
        char name[256]; clGetDeviceInfo(d, CL_DEVICE_NAME, sizeof name, name, nullptr);
        cl_int e; cl_context c = clCreateContext(nullptr, 1, &d, nullptr, nullptr, &e);
        cl_command_queue q = clCreateCommandQueue(c, d, 0, &e);
        for (size_t mb : {1, 16, 160, 400}) {
            size_t bytes = mb << 20; cl_uint zero = 0;
            auto t0 = std::chrono::steady_clock::now();
            const int n = 10;
            for (int i = 0; i < n; ++i) {
                cl_mem m = clCreateBuffer(c, CL_MEM_READ_WRITE, bytes, nullptr, &e);
                clEnqueueFillBuffer(q, m, &zero, 4, 0, bytes, 0, nullptr, nullptr);
                clFinish(q); clReleaseMemObject(m);
            }
            auto t1 = std::chrono::steady_clock::now();
            cl_mem m = clCreateBuffer(c, CL_MEM_READ_WRITE, bytes, nullptr, &e);
            for (int i = 0; i < n; ++i) { clEnqueueFillBuffer(q, m, &zero, 4, 0, bytes, 0, nullptr, nullptr); clFinish(q); }
            auto t2 = std::chrono::steady_clock::now();
            std::vector<char> host(bytes);
            auto t3 = std::chrono::steady_clock::now();
            for (int i = 0; i < n; ++i) clEnqueueReadBuffer(q, m, CL_TRUE, 0, bytes, host.data(), 0, nullptr, nullptr);
            auto t4 = std::chrono::steady_clock::now();
            clReleaseMemObject(m);
            auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
            std::printf("%s: %zu MB: alloc+fill+release %.3f ms, fill reused %.3f ms, read back (pageable) %.3f ms\n", name, mb,
                        ms(t0, t1) / n, ms(t1, t2) / n, ms(t3, t4) / n);
        }
        // Empty kernel-free wait: finish on an empty queue, and a tiny blocking read.
        cl_mem m = clCreateBuffer(c, CL_MEM_READ_WRITE, 64, nullptr, &e); cl_ulong v;
        auto t0 = std::chrono::steady_clock::now();
        for (int i = 0; i < 100; ++i) clEnqueueReadBuffer(q, m, CL_TRUE, 0, 8, &v, 0, nullptr, nullptr);
        auto t1 = std::chrono::steady_clock::now();
        std::printf("%s: 8-byte blocking read %.4f ms\n", name, std::chrono::duration<double, std::milli>(t1 - t0).count() / 100);
        clReleaseMemObject(m); clReleaseCommandQueue(q); clReleaseContext(c);
    }
}
