// The thread pool, the renderer's configuration, and the heap's populating (exec/fresh_pages.hpp).
#include <gtest/gtest.h>

#include <malloc.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <latch>
#include <stdexcept>
#include <thread>
#include <string>
#include <vector>

#include "exec/fresh_pages.hpp"
#include "facet/detail/thread_pool.hpp"
#include "facet/renderer.hpp"
#include "facet/sandbox.hpp"

namespace {

using namespace facet;

TEST(ThreadPool, RunsEveryTaskExactlyOnce) {
    for (int threads : {1, 2, 5}) {
        detail::ThreadPool pool(threads);
        EXPECT_EQ(pool.size(), threads);
        for (std::size_t count : {0u, 1u, 7u, 1000u}) {
            std::vector<std::atomic<int>> hits(count);
            pool.parallel_for(count, [&](std::size_t i) { hits[i]++; });
            for (std::size_t i = 0; i < count; ++i) EXPECT_EQ(hits[i].load(), 1) << threads << " " << i;
        }
    }
}

// parallel_for's `done`: once per worker that ran tasks, on that worker, after its last task and
// before the loop returns; not for a worker that ran none; also when a task threw.
TEST(ThreadPool, DoneRunsOnceAfterTheLastTaskOfEachWorkerThatRanOne) {
    for (int threads : {1, 2, 5}) {
        detail::ThreadPool pool(threads);
        for (std::size_t count : {0u, 1u, 7u, 1000u}) {
            std::vector<std::atomic<int>> tasks(static_cast<std::size_t>(threads)), dones(tasks.size());
            std::vector<int> tasks_at_done(tasks.size(), -1);
            std::vector<std::thread::id> task_thread(tasks.size()), done_thread(tasks.size());
            pool.parallel_for(
                count,
                [&](std::size_t, int worker) {
                    const auto w = static_cast<std::size_t>(worker);
                    tasks[w]++;
                    task_thread[w] = std::this_thread::get_id();
                },
                [&](int worker) {
                    const auto w = static_cast<std::size_t>(worker);
                    dones[w]++;
                    tasks_at_done[w] = tasks[w].load();
                    done_thread[w] = std::this_thread::get_id();
                });
            int total = 0;
            for (std::size_t w = 0; w < tasks.size(); ++w) {
                total += tasks[w].load();
                EXPECT_EQ(dones[w].load(), tasks[w].load() > 0 ? 1 : 0) << threads << " " << count << " " << w;
                if (tasks[w].load() == 0) continue;
                EXPECT_EQ(tasks_at_done[w], tasks[w].load()) << threads << " " << count << " " << w;
                EXPECT_EQ(done_thread[w], task_thread[w]) << threads << " " << count << " " << w;
            }
            EXPECT_EQ(total, static_cast<int>(count));
        }
    }
    detail::ThreadPool pool(2);
    std::atomic<int> dones{0};
    EXPECT_THROW(pool.parallel_for(
                     4, [](std::size_t) { throw std::runtime_error("every task"); }, [&](int) { dones++; }),
                 std::runtime_error);
    EXPECT_GE(dones.load(), 1);
}

// parallel_for_shares: every task once, `done` as parallel_for's; each worker starts on its own
// contiguous share in order, and a worker whose share is done takes the others' tasks from the back.
TEST(ThreadPool, SharesRunEveryTaskOnceAndTheIdleWorkerTakesTheOthersFromTheBack) {
    for (int threads : {1, 2, 5}) {
        detail::ThreadPool pool(threads);
        for (std::size_t count : {0u, 1u, 7u, 1000u}) {
            std::vector<std::atomic<int>> hits(count), tasks(static_cast<std::size_t>(threads)), dones(tasks.size());
            pool.parallel_for_shares(
                count,
                [&](std::size_t i, int worker) {
                    hits[i]++;
                    tasks[static_cast<std::size_t>(worker)]++;
                },
                [&](int worker) { dones[static_cast<std::size_t>(worker)]++; });
            for (std::size_t i = 0; i < count; ++i) EXPECT_EQ(hits[i].load(), 1) << threads << " " << i;
            for (std::size_t w = 0; w < tasks.size(); ++w)
                EXPECT_EQ(dones[w].load(), tasks[w].load() > 0 ? 1 : 0) << threads << " " << count << " " << w;
        }
    }
    // Worker 0 holds its first task (0) until the other 99 are done; worker 1 waits in its first
    // task until worker 0 has begun, so it cannot have taken task 0 first.
    detail::ThreadPool pool(2);
    constexpr std::size_t count = 100;
    std::vector<std::size_t> order[2];
    std::atomic<bool> started{false};
    std::atomic<int> finished{0};
    const auto wait_for = [](const auto& ok) {
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
        while (!ok() && std::chrono::steady_clock::now() < until) std::this_thread::yield();
        return ok();
    };
    pool.parallel_for_shares(count, [&](std::size_t i, int worker) {
        order[static_cast<std::size_t>(worker)].push_back(i);
        if (worker == 0 && order[0].size() == 1) {
            started = true;
            EXPECT_TRUE(wait_for([&] { return finished.load() == static_cast<int>(count) - 1; }));
        }
        if (worker == 1 && order[1].size() == 1) {
            EXPECT_TRUE(wait_for([&] { return started.load(); }));
        }
        finished++;
    });
    std::vector<std::size_t> expected;
    for (std::size_t i = count / 2; i < count; ++i) expected.push_back(i);
    for (std::size_t i = count / 2; i-- > 1;) expected.push_back(i);
    EXPECT_EQ(order[0], std::vector<std::size_t>{0});
    EXPECT_EQ(order[1], expected);
}

TEST(ThreadPool, ExceptionsReachTheCallerAndThePoolStaysUsable) {
    detail::ThreadPool pool(3);
    EXPECT_THROW(pool.parallel_for(100, [](std::size_t i) {
        if (i == 42) throw std::runtime_error("task 42");
    }), std::runtime_error);
    std::atomic<int> n{0};
    pool.parallel_for(50, [&](std::size_t) { n++; });
    EXPECT_EQ(n.load(), 50);
}

// The thread each worker index of the pool runs on: two tasks that wait for each other, so that
// both workers take one.
std::vector<std::thread::id> worker_threads(detail::ThreadPool& pool) {
    std::vector<std::thread::id> ids(2);
    std::latch both(2);
    pool.parallel_for(2, [&](std::size_t, int worker) {
        ids[static_cast<std::size_t>(worker)] = std::this_thread::get_id();
        both.arrive_and_wait();
    });
    return ids;
}

// A pool that ends leaves its thread to the next pool (a process starts each thread once), and
// pools alive at once have threads of their own.
TEST(ThreadPool, ThePoolsThreadGoesToTheNextPool) {
    std::thread::id first;
    {
        detail::ThreadPool pool(2);
        first = worker_threads(pool)[1];
        EXPECT_NE(first, std::this_thread::get_id());
    }
    detail::ThreadPool next(2);
    EXPECT_EQ(worker_threads(next)[1], first);
    detail::ThreadPool beside(2);
    const std::thread::id other = worker_threads(beside)[1];
    EXPECT_NE(other, first);
    EXPECT_NE(other, std::this_thread::get_id());
    EXPECT_EQ(worker_threads(next)[1], first);
}

#if !defined(__SANITIZE_THREAD__)  // TSan does not start threads after a multi-threaded fork
// A forked child has none of the parent's spare threads: its pools start their own.
TEST(ThreadPool, AForkedChildStartsThreadsOfItsOwn) {
    { detail::ThreadPool pool(2); (void)worker_threads(pool); }  // a spare thread in this process
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        alarm(20);  // a pool waiting for a thread that is not there would hang
        detail::ThreadPool pool(2);
        const std::vector<std::thread::id> ids = worker_threads(pool);
        _exit(ids[1] != ids[0] ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
}
#endif

TEST(ThreadPool, ZeroMeansOnePerCore) {
    detail::ThreadPool pool(0);
    EXPECT_GE(pool.size(), 1);
}

// Whether every page of [begin, begin + bytes) is in memory.
bool resident(std::uintptr_t begin, std::size_t bytes) {
    const std::uintptr_t page = 4096, first = begin & ~(page - 1);
    std::vector<unsigned char> in((begin + bytes - first + page - 1) / page);
    if (mincore(reinterpret_cast<void*>(first), begin + bytes - first, in.data()) != 0) return false;
    for (const unsigned char p : in)
        if (!(p & 1)) return false;
    return true;
}

TEST(FreshPages, PopulatingTheHeapTopFaultsItInAndChangesNoBlock) {
    if (sanitizer_build()) GTEST_SKIP() << "a sanitizer's allocator has no heap top";
    // A heap top of fresh pages: the heap grows by 4 MiB more than a block larger than its free top
    // (from the heap, not mapped on its own).
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TOP_PAD, 4 << 20);
    const std::size_t size = mallinfo2().keepcost + 4096;
    auto* block = static_cast<unsigned char*>(std::malloc(size));
    mallopt(M_TOP_PAD, 128 << 10);
    mallopt(M_MMAP_THRESHOLD, 128 << 10);
    ASSERT_NE(block, nullptr);
    for (std::size_t i = 0; i < size; ++i) block[i] = static_cast<unsigned char>(i * 7);
    const auto end = reinterpret_cast<std::uintptr_t>(sbrk(0));
    const std::uintptr_t top = end - mallinfo2().keepcost;
    ASSERT_GE(end - top, std::size_t{3} << 20);
    if (resident(top + (1 << 20), 1 << 20)) GTEST_SKIP() << "the heap's new top is in memory already (huge pages always?)";

    EXPECT_EQ(detail::populate_heap_top(2 << 20, [] { return false; }), 0u);  // go_on false: nothing
    EXPECT_FALSE(resident(top + (1 << 20), 1 << 20));
    // go_on is asked before each 2 MiB page: yes for the first (the part of one above the top) and
    // the next, then no; at most 3 MiB.
    const std::uintptr_t huge = 2 << 20, first = top & ~std::uintptr_t{4095};
    const std::uintptr_t last = std::min({first + (3 << 20), ((first + huge) & ~(huge - 1)) + huge, end});
    int asked = 0;
    EXPECT_EQ(detail::populate_heap_top(3 << 20, [&] { return ++asked <= 2; }), last - first);
    EXPECT_EQ(asked, last - first == 3u << 20 ? 2 : 3);
    EXPECT_TRUE(resident(first, last - first));
    for (std::size_t i = 0; i < size; ++i) ASSERT_EQ(block[i], static_cast<unsigned char>(i * 7)) << i;
    std::free(block);
}

TEST(FreshPages, ARecyclingScopeHandsAReleasedArrayOnClearedAndUnmapsItAtItsEnd) {
    constexpr std::size_t n = std::size_t{6} << 20;  // 6 MiB: mapped, not calloc'd
    const auto fill = [](const detail::ZeroedArray<std::uint8_t>& a, std::size_t count) {
        std::memset(a.data(), 0xA5, count);
    };
    std::uint8_t* first = nullptr;
    {
        const detail::RecycleFreshPages scope;
        {
            detail::ZeroedArray<std::uint8_t> a(n);
            first = a.data();
            fill(a, n);
        }
        // A smaller array takes the kept mapping, cleared for its size; then a larger one than any
        // kept gets one of its own.
        detail::ZeroedArray<std::uint32_t> b(n / 8);
        EXPECT_EQ(static_cast<void*>(b.data()), static_cast<void*>(first));
        for (std::size_t i = 0; i < n / 8; ++i) ASSERT_EQ(b[i], 0u) << i;
        detail::ZeroedArray<std::uint8_t> c(2 * n);
        EXPECT_NE(c.data(), first);
        for (std::size_t i = 0; i < 2 * n; i += 4096) ASSERT_EQ(c[i], 0u) << i;
    }
    // The scope's end unmapped what was kept (c's mapping, the larger): outside one, a released
    // array's mapping is unmapped and the next one maps its own, zero.
    EXPECT_EQ(detail::fresh_detail::recycled.raw, nullptr);
    {
        detail::ZeroedArray<std::uint8_t> d(n);
        fill(d, n);
    }
    EXPECT_EQ(detail::fresh_detail::recycled.raw, nullptr);
    const detail::ZeroedArray<std::uint8_t> e(n);
    for (std::size_t i = 0; i < n; i += 4096) ASSERT_EQ(e[i], 0u) << i;
}

TEST(FreshPages, ARecyclingScopeGrowsTheKeptMappingForALargerArray) {
    constexpr std::size_t n = std::size_t{6} << 20;
    const detail::RecycleFreshPages scope;
    {
        detail::ZeroedArray<std::uint8_t> a(n);
        std::memset(a.data(), 0xA5, n);
    }
    ASSERT_NE(detail::fresh_detail::recycled.raw, nullptr);
    // A larger array takes the kept mapping (none kept after it), grown: zero throughout, what the
    // first array wrote cleared; and writable throughout.
    detail::ZeroedArray<std::uint8_t> b(3 * n);
    EXPECT_EQ(detail::fresh_detail::recycled.raw, nullptr);
    EXPECT_EQ(std::count(b.data(), b.data() + 3 * n, std::uint8_t{0}), static_cast<std::ptrdiff_t>(3 * n));
    std::memset(b.data(), 0x5A, 3 * n);
}

TEST(Renderer, RejectsBadConfigurationAndViewports) {
    EXPECT_THROW(Renderer({.tile_size = 48}), FacetError);
    EXPECT_THROW(Renderer({.tile_size = 128}), FacetError);
    EXPECT_THROW(Renderer({.tile_size = 4}), FacetError);
    EXPECT_THROW(Framebuffer(0, 10), FacetError);
    EXPECT_THROW(Framebuffer(10, k_max_target_size + 1), FacetError);

    Renderer r({.threads = 1});
    Framebuffer fb(16, 16);
    const auto shader = make_shader<0>([](std::uint32_t, Varyings<0>&) { return Vec4{0, 0, 0, 1}; },
                                       [](const FragmentIn<0>&) { return Vec4{1, 1, 1, 1}; });
    DrawState state;
    state.viewport = {0, 0, -4, 16};
    EXPECT_THROW(r.draw(fb, state, DrawInput{3, {}}, shader), FacetError);
    state.viewport = {-1, 0, 8, 8};
    EXPECT_THROW(r.draw(fb, state, DrawInput{3, {}}, shader), FacetError);
}

TEST(Renderer, ViewportLimitsWhereTrianglesLand) {
    Renderer r({.threads = 2, .tile_size = 8});
    Framebuffer fb(32, 32);
    fb.clear({0, 0, 0, 1});
    // A triangle far larger than clip space: it covers its whole viewport and nothing else.
    const Vec4 big[3] = {{-4, -4, 0.5f, 1}, {4, -4, 0.5f, 1}, {0, 6, 0.5f, 1}};
    const auto shader = make_shader<0>([&](std::uint32_t i, Varyings<0>&) { return big[i]; },
                                       [](const FragmentIn<0>&) { return Vec4{1, 1, 1, 1}; });
    DrawState state;
    state.viewport = {4, 8, 10, 12};
    r.draw(fb, state, DrawInput{3, {}}, shader);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const bool inside = x >= 4 && x < 14 && y >= 8 && y < 20;
            EXPECT_EQ(fb.colour(x, y).r, inside ? 255 : 0) << x << "," << y;
        }
}

TEST(Renderer, ExceptionFromAShaderPropagatesAndTheRendererStillWorks) {
    Renderer r({.threads = 2});
    Framebuffer fb(64, 64);
    const Vec4 tri[3] = {{-1, -1, 0.5f, 1}, {1, -1, 0.5f, 1}, {0, 1, 0.5f, 1}};
    const auto throwing = make_shader<0>([&](std::uint32_t i, Varyings<0>&) { return tri[i]; },
                                         [](const FragmentIn<0>&) -> Vec4 { throw std::runtime_error("shader"); });
    EXPECT_THROW(r.draw(fb, DrawState{}, DrawInput{3, {}}, throwing), std::runtime_error);
    const auto fine = make_shader<0>([&](std::uint32_t i, Varyings<0>&) { return tri[i]; },
                                     [](const FragmentIn<0>&) { return Vec4{0, 1, 0, 1}; });
    fb.clear({0, 0, 0, 1});
    const DrawStats s = r.draw(fb, DrawState{}, DrawInput{3, {}}, fine);
    EXPECT_EQ(s.triangles_rasterized, 1u);
    EXPECT_EQ(fb.colour(32, 40).g, 255);
}

TEST(Renderer, StatsCountInvalidAndCulledTriangles) {
    Renderer r({.threads = 1});
    Framebuffer fb(32, 32);
    const Vec4 pos[4] = {{-1, -1, 0.5f, 1}, {1, -1, 0.5f, 1}, {0, 1, 0.5f, 1}, {NAN, 0, 0.5f, 1}};
    const auto shader = make_shader<0>([&](std::uint32_t i, Varyings<0>&) { return pos[i]; },
                                       [](const FragmentIn<0>&) { return Vec4{1, 1, 1, 1}; });
    // front (CCW), back (CW), NaN vertex, out-of-range index, zero area, and a trailing partial triangle.
    const std::uint32_t idx[] = {0, 1, 2, 0, 2, 1, 0, 1, 3, 0, 1, 9, 0, 0, 1, 2, 1};
    const DrawStats s = r.draw(fb, DrawState{}, DrawInput{4, idx}, shader);
    EXPECT_EQ(s.triangles_in, 5u);
    EXPECT_EQ(s.triangles_invalid, 2u);
    EXPECT_EQ(s.triangles_culled, 2u);  // the back face and the zero-area one
    EXPECT_EQ(s.triangles_rasterized, 1u);
}

TEST(ThreadPool, EveryTaskThrowingNeitherDeadlocksNorLosesTheException) {
    for (int threads : {2, 4}) {
        detail::ThreadPool pool(threads);
        for (int round = 0; round < 20; ++round) {
            std::atomic<int> ran{0};
            try {
                pool.parallel_for(64, [&](std::size_t i) {
                    ran++;
                    throw std::runtime_error("task " + std::to_string(i));
                });
                ADD_FAILURE() << "nothing thrown";
            } catch (const std::runtime_error& e) {
                EXPECT_EQ(std::string(e.what()).rfind("task ", 0), 0u);
            }
            // Tasks after the first failure are skipped, but at least one ran per thread at most.
            EXPECT_GE(ran.load(), 1);
            EXPECT_LE(ran.load(), threads);
        }
        std::atomic<int> n{0};
        pool.parallel_for(100, [&](std::size_t) { n++; });
        EXPECT_EQ(n.load(), 100);
    }
}

TEST(Renderer, ExceptionFromTheVertexStagePropagatesAndTheRendererStillWorks) {
    Renderer r({.threads = 3});
    Framebuffer fb(64, 64);
    const std::uint32_t n = 5 * 4096;  // several vertex blocks, run on several threads
    const Vec4 tri[3] = {{-1, -1, 0.5f, 1}, {1, -1, 0.5f, 1}, {0, 1, 0.5f, 1}};
    const auto throwing = make_shader<0>(
        [&](std::uint32_t i, Varyings<0>&) {
            if (i == n - 100) throw std::runtime_error("vertex");
            return tri[i % 3];
        },
        [](const FragmentIn<0>&) { return Vec4{1, 0, 0, 1}; });
    fb.clear({0, 0, 0, 1});
    EXPECT_THROW(r.draw(fb, DrawState{}, DrawInput{n, {}}, throwing), std::runtime_error);
    EXPECT_EQ(fb.colour(32, 40).r, 0);  // the draw stopped before the fragment stage
    const auto fine = make_shader<0>([&](std::uint32_t i, Varyings<0>&) { return tri[i % 3]; },
                                     [](const FragmentIn<0>&) { return Vec4{0, 1, 0, 1}; });
    const DrawStats s = r.draw(fb, DrawState{}, DrawInput{n, {}}, fine);
    EXPECT_EQ(s.triangles_in, n / 3);
    EXPECT_EQ(fb.colour(32, 40).g, 255);
}

// A fragment shader that throws on many tiles at once, on every thread: the first exception
// reaches the caller, the others are dropped, and nothing hangs.
TEST(Renderer, ExceptionsFromManyTilesAtOnceReachTheCallerOnce) {
    Renderer r({.threads = 4, .tile_size = 8});
    Framebuffer fb(128, 128);
    const Vec4 tri[3] = {{-1, -1, 0.5f, 1}, {3, -1, 0.5f, 1}, {-1, 3, 0.5f, 1}};
    const auto throwing = make_shader<0>([&](std::uint32_t i, Varyings<0>&) { return tri[i]; },
                                         [](const FragmentIn<0>& in) -> Vec4 {
                                             if (in.pos_screen.x > 4) throw std::runtime_error("tile");
                                             return {1, 1, 1, 1};
                                         });
    for (int round = 0; round < 10; ++round)
        EXPECT_THROW(r.draw(fb, DrawState{}, DrawInput{3, {}}, throwing), std::runtime_error);
}

}  // namespace
