// No allocation per frame (the runtime's rule): a counting allocator around the runtime's frame
// entry points that run without a GL driver: the CPU backend and the GL ES 1.1 / GL ES 2
// emulator (which shares the GL paths' vertex set-up, exposure, staging and pass schedule
// with sepal_draw). A GL frame is not counted: the driver (Mesa) allocates on its own.
//
// The counter replaces the global operator new and malloc/calloc/realloc for this test
// binary (glibc's __libc_* underneath) and counts only on the thread that asked, while it
// asked. Sanitizer builds keep their own allocators: there the test says so and checks only
// that the frames draw.
#include <doctest/doctest.h>

#include <cstdlib>
#include <memory>
#include <new>
#include <vector>

#include "bake/asset_file.h"
#include "bake/bake.h"
#include "brdf/brdf.h"
#include "common/scene_draw.h"
#include "common/scene_flags.h"
#include "material_fixtures.h"
#include "sepal/internal/sepal_emulate.h"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define SEPAL_COUNTING_ALLOCATOR 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define SEPAL_COUNTING_ALLOCATOR 0
#endif
#endif
#ifndef SEPAL_COUNTING_ALLOCATOR
#define SEPAL_COUNTING_ALLOCATOR 1
#endif

namespace {
// Thread-local and zero-initialized: no allocation to reach it (initial-exec TLS).
thread_local bool t_counting = false;
thread_local long t_allocations = 0;

struct Counting {
    Counting() { t_allocations = 0, t_counting = true; }
    ~Counting() { t_counting = false; }
    long count() const { return t_allocations; }
};
}  // namespace

#if SEPAL_COUNTING_ALLOCATOR
extern "C" {
void* __libc_malloc(size_t);
void* __libc_calloc(size_t, size_t);
void* __libc_realloc(void*, size_t);
void __libc_free(void*);

void* malloc(size_t n) {
    if (t_counting) ++t_allocations;
    return __libc_malloc(n);
}
void* calloc(size_t n, size_t s) {
    if (t_counting) ++t_allocations;
    return __libc_calloc(n, s);
}
void* realloc(void* p, size_t n) {
    if (t_counting) ++t_allocations;
    return __libc_realloc(p, n);
}
void free(void* p) { __libc_free(p); }
}

void* operator new(size_t n) {
    if (t_counting) ++t_allocations;
    if (void* p = __libc_malloc(n ? n : 1)) return p;
    throw std::bad_alloc();
}
void* operator new[](size_t n) { return operator new(n); }
void* operator new(size_t n, const std::nothrow_t&) noexcept {
    if (t_counting) ++t_allocations;
    return __libc_malloc(n ? n : 1);
}
void* operator new[](size_t n, const std::nothrow_t& t) noexcept { return operator new(n, t); }
void operator delete(void* p) noexcept { __libc_free(p); }
void operator delete[](void* p) noexcept { __libc_free(p); }
void operator delete(void* p, size_t) noexcept { __libc_free(p); }
void operator delete[](void* p, size_t) noexcept { __libc_free(p); }
#endif

TEST_CASE("runtime: no allocation per frame on the CPU backend and the GL ES emulator (counting allocator)") {
    // The counter itself must see an allocation, or a zero below proves nothing.
    long probe;
    {
        Counting c;
        std::unique_ptr<std::vector<int>> v(new std::vector<int>(1000));
        void* volatile p = std::malloc(64);  // volatile: a malloc/free pair may be elided
        std::free(p);
        probe = c.count();
    }
    if (SEPAL_COUNTING_ALLOCATOR) CHECK(probe >= 3);
    if (!SEPAL_COUNTING_ALLOCATOR) MESSAGE("sanitizer build: its allocator stays; frames drawn, not counted");
    std::string err;
    const std::vector<uint8_t> bytes = material_fx::encode(
        material_fx::bake_small("ashikhmin-shirley", sepal::Param::GsHalf, sepal::Method::ACLS, 2, true, 16, 32));
    auto asset = std::make_unique<sepal_asset>();
    sepal_error e = {};
    REQUIRE(sepal_asset_parse(bytes.data(), bytes.size(), asset.get(), &e) == SEPAL_OK);
    sepal_ports::SceneSetup setup;
    setup.width = setup.height = 96;
    REQUIRE_MESSAGE(sepal_ports::load_scene_mesh(&setup, &err), err);
    // Two lights: the per-light loops run more than once.
    setup.scene.lights[1] = setup.scene.lights[0];
    setup.scene.lights[1].position[0] = -setup.scene.lights[1].position[0];
    setup.scene.light_count = 2;

    sepal_ports::CpuFrame frame;
    const sepal_cpu_desc cd = sepal_ports::scene_cpu_desc(asset.get(), setup, &frame, nullptr);
    sepal_ports::EmulatedFrame em;
    for (int gles_version : {0, 1, 2}) {
        CAPTURE(gles_version);  // 0: the CPU backend
        sepal_draw_stats stats = {};
        const sepal_emulate_desc ed =
            sepal_ports::scene_emulate_desc(asset.get(), setup, gles_version, 0, &em, &stats);
        for (int f = 0; f < 3; ++f) {
            sepal_result res;
            long n;
            {
                Counting c;
                res = gles_version == 0 ? sepal_draw_cpu(&cd, &e) : sepal_emulate_draw(&ed, &e);
                n = c.count();
            }
            REQUIRE_MESSAGE(res == SEPAL_OK, e.message);
            CHECK(n == 0);
        }
    }
    // The frames drew something (a lit sphere), so the zero counted real work.
    long lit = 0;
    for (size_t p = 0; p < em.rgba.size(); p += 4) lit += em.rgba[p] > 0;
    CHECK(lit > 500);
}
