// The worker processes' sandbox (issue 20, facet/sandbox.hpp, docs/RELIABILITY.md). A test hook
// (FACET_TEST_SANDBOX_PROBE) makes the job try, where it starts, what a compromised reader would:
// open a socket and connect to a listener of this test, run a program, start a process, read a file
// outside the model's folder, write outside the output's folder. Each must be refused in the
// worker of `facet render` and `facet thumbs` and in load_model_isolated's child, while the same
// probes succeed without the sandbox (--no-isolation), which shows the probes can see an escape.
// Renders of real models stay the same bytes under the sandbox, with 1 and 2 threads.
#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "facet/model.hpp"
#include "facet/sandbox.hpp"
#include "support/cli.hpp"
#include "support/test_data.hpp"

namespace {

namespace fs = std::filesystem;
using facet_test::k_box_obj;
using facet_test::ScopedEnv;
using facet_test::CliRun;
using facet_test::run_facet;
using facet_test::write_file;

// A TCP listener on 127.0.0.1 at a free port, non-blocking, closed by its destructor.
class Listener {
public:
    Listener() {
        fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        socklen_t size = sizeof a;
        if (fd_ < 0 || bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 || listen(fd_, 4) != 0 ||
            getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &size) != 0)
            ADD_FAILURE() << "cannot listen on 127.0.0.1";
        port_ = ntohs(a.sin_port);
    }
    ~Listener() { close(fd_); }
    Listener(const Listener&) = delete;
    Listener& operator=(const Listener&) = delete;
    int port() const { return port_; }
    // Whether a connection has arrived (the probe has finished when facet has exited).
    bool connected() const {
        const int c = accept(fd_, nullptr, nullptr);
        if (c >= 0) close(c);
        return c >= 0;
    }

private:
    int fd_ = -1;
    int port_ = 0;
};

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// What the probe printed for `action`: "allowed", "refused (...)", or "" when it did not run.
std::string probe_result(const std::string& err, const std::string& action) {
    const std::string mark = "facet: sandbox probe " + action + ": ";
    const std::size_t at = err.find(mark);
    if (at == std::string::npos) return "";
    const std::size_t end = err.find('\n', at);
    return err.substr(at + mark.size(), end - at - mark.size());
}

bool refused(const std::string& result) { return result.rfind("refused", 0) == 0; }

struct Folders {
    fs::path model_dir, model, outside_file, out_dir, other_dir;
};

Folders make_folders(const std::string& name) {
    Folders s;
    const fs::path root = facet_test::test_temp_dir("facet_sandbox_" + name);
    s.model_dir = root / "model";
    fs::create_directories(s.model_dir);
    fs::create_directories(root / "private");
    s.model = write_file(s.model_dir / "box.obj", k_box_obj);
    s.outside_file = write_file(root / "private" / "secret.txt", "secret\n");
    s.out_dir = root / "out";
    s.other_dir = root / "elsewhere";
    fs::create_directories(s.out_dir);
    fs::create_directories(s.other_dir);
    return s;
}

std::string probes(const Folders& s, int port, bool with_exec) {
    return "socket:" + std::to_string(port) + (with_exec ? ";exec" : "") + ";fork;thread;read:" + s.outside_file.string() +
           ";read:" + s.model.string() + ";write:" + (s.other_dir / "w.txt").string() + ";write:" +
           (s.out_dir / "w.txt").string();
}

// The probes a sandboxed job printed: everything a compromised reader could use is refused (the
// file rules only where the kernel offers Landlock), what the job needs is allowed.
void expect_confined(const Folders& s, const std::string& err, const Listener& listener, bool landlock) {
    EXPECT_TRUE(refused(probe_result(err, "socket:" + std::to_string(listener.port())))) << err;
    EXPECT_FALSE(listener.connected()) << "the worker reached the test's listener";
    EXPECT_TRUE(refused(probe_result(err, "exec"))) << err;
    EXPECT_TRUE(refused(probe_result(err, "fork"))) << err;
    EXPECT_EQ(probe_result(err, "thread"), "allowed") << err;
    EXPECT_EQ(refused(probe_result(err, "read:" + s.outside_file.string())), landlock) << err;
    EXPECT_EQ(probe_result(err, "read:" + s.model.string()), "allowed") << err;
    EXPECT_EQ(refused(probe_result(err, "write:" + (s.other_dir / "w.txt").string())), landlock) << err;
    EXPECT_EQ(probe_result(err, "write:" + (s.out_dir / "w.txt").string()), "allowed") << err;
}

TEST(Sandbox, RenderWorkerCannotConnectExecForkOrReadOutside) {
    const Folders s = make_folders("render");
    const Listener listener;
    const ScopedEnv hook("FACET_TEST_SANDBOX_PROBE", probes(s, listener.port(), true));
    const CliRun r = run_facet({"render", s.model.string(), "-o", (s.out_dir / "box.png").string(), "--size", "32x24"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(s.out_dir / "box.png")) << "the render under the sandbox failed";
    expect_confined(s, r.err, listener, facet::landlock_abi() > 0);
}

TEST(Sandbox, ThumbsWorkersAreConfinedToo) {
    const Folders s = make_folders("thumbs");
    const Listener listener;
    const ScopedEnv hook("FACET_TEST_SANDBOX_PROBE", probes(s, listener.port(), true));
    const CliRun r = run_facet({"thumbs", s.model.string(), "-o", s.out_dir.string(), "--size", "32"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(s.out_dir / "box.obj.png"));
    expect_confined(s, r.err, listener, facet::landlock_abi() > 0);
}

// How many times the probe printed `action`'s result: one per worker confined.
std::size_t probe_count(const std::string& err, const std::string& action) {
    std::size_t n = 0;
    const std::string mark = "facet: sandbox probe " + action + ": ";
    for (std::size_t at = err.find(mark); at != std::string::npos; at = err.find(mark, at + 1)) ++n;
    return n;
}

// A manifest's objects in two folders: by default one worker serves both (one confinement), and its
// sandbox reads both folders and still nothing else; --worker-sharing folder gives each folder a
// worker that cannot read the other's.
TEST(Sandbox, ThumbsWorkersServingABatchReadOnlyItsObjectsFolders) {
    const Folders s = make_folders("batch");
    fs::create_directories(s.model_dir.parent_path() / "second");
    const fs::path second = write_file(s.model_dir.parent_path() / "second" / "box.obj", k_box_obj);
    const fs::path manifest = write_file(s.model_dir.parent_path() / "objects.txt", s.model.string() + "\n" + second.string() + "\n");
    const std::string read_second = "read:" + second.string(), read_outside = "read:" + s.outside_file.string();
    const ScopedEnv hook("FACET_TEST_SANDBOX_PROBE", read_second + ";" + read_outside);
    const bool landlock = facet::landlock_abi() > 0;

    const CliRun batch = run_facet({"thumbs", "--manifest", manifest.string(), "-o", s.out_dir.string(), "--size", "16",
                                    "--threads", "1"});
    EXPECT_EQ(batch.exit_code, 0) << batch.err;
    EXPECT_EQ(probe_count(batch.err, read_second), 1u) << "one worker for both objects: " << batch.err;
    EXPECT_EQ(probe_result(batch.err, read_second), "allowed") << batch.err;
    EXPECT_EQ(refused(probe_result(batch.err, read_outside)), landlock) << batch.err;

    const CliRun folder = run_facet({"thumbs", "--manifest", manifest.string(), "-o", (s.out_dir / "f").string(),
                                     "--size", "16", "--threads", "1", "--worker-sharing", "folder"});
    EXPECT_EQ(folder.exit_code, 0) << folder.err;
    EXPECT_EQ(probe_count(folder.err, read_second), 2u) << "a worker per folder: " << folder.err;
    // The first object's worker runs first (one at a time).
    EXPECT_EQ(refused(probe_result(folder.err, read_second)), landlock) << folder.err;
    std::size_t images = 0;  // the same images either way
    for (const auto& e : fs::directory_iterator(s.out_dir)) {
        if (!e.is_regular_file()) continue;
        ++images;
        EXPECT_EQ(facet_test::read_file(e.path()), facet_test::read_file(s.out_dir / "f" / e.path().filename()))
            << e.path();
    }
    EXPECT_EQ(images, 2u);
}

// The control: without a worker there is no sandbox, and the same probes get through (exec is left
// out, as it would replace facet itself).
TEST(Sandbox, ProbesSeeEverythingWithoutTheSandbox) {
    const Folders s = make_folders("control");
    const Listener listener;
    const ScopedEnv hook("FACET_TEST_SANDBOX_PROBE", probes(s, listener.port(), false));
    const CliRun r = run_facet({"render", s.model.string(), "-o", (s.out_dir / "box.png").string(), "--size", "32x24",
                                "--no-isolation"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(probe_result(r.err, "socket:" + std::to_string(listener.port())), "allowed") << r.err;
    EXPECT_TRUE(listener.connected());
    EXPECT_EQ(probe_result(r.err, "fork"), "allowed") << r.err;
    EXPECT_EQ(probe_result(r.err, "read:" + s.outside_file.string()), "allowed") << r.err;
    EXPECT_EQ(probe_result(r.err, "write:" + (s.other_dir / "w.txt").string()), "allowed") << r.err;
}

// A kernel without Landlock (or, should it happen, without seccomp): the render goes on with what
// remains, and what remains still holds.
TEST(Sandbox, EachPartAloneStillHoldsAndNeverFailsTheRender) {
    const Folders s = make_folders("fallback");
    {
        const Listener listener;
        const ScopedEnv hook("FACET_TEST_SANDBOX_PROBE", probes(s, listener.port(), true));
        const ScopedEnv without("FACET_TEST_SANDBOX_WITHOUT", "landlock");
        const CliRun r = run_facet({"render", s.model.string(), "-o", (s.out_dir / "a.png").string(), "--size", "32x24"});
        EXPECT_EQ(r.exit_code, 0) << r.err;
        EXPECT_TRUE(fs::exists(s.out_dir / "a.png"));
        expect_confined(s, r.err, listener, /*landlock=*/false);
    }
    if (facet::landlock_abi() > 0) {
        const Listener listener;
        const ScopedEnv hook("FACET_TEST_SANDBOX_PROBE", "socket:" + std::to_string(listener.port()) + ";fork;read:" +
                                                             s.outside_file.string());
        const ScopedEnv without("FACET_TEST_SANDBOX_WITHOUT", "seccomp");
        const CliRun r = run_facet({"render", s.model.string(), "-o", (s.out_dir / "b.png").string(), "--size", "32x24"});
        EXPECT_EQ(r.exit_code, 0) << r.err;
        EXPECT_TRUE(fs::exists(s.out_dir / "b.png"));
        EXPECT_EQ(probe_result(r.err, "fork"), "allowed") << r.err;  // seccomp's part
        EXPECT_TRUE(refused(probe_result(r.err, "read:" + s.outside_file.string()))) << r.err;
        // Landlock refuses TCP connections from ABI 4 on.
        EXPECT_EQ(refused(probe_result(r.err, "socket:" + std::to_string(listener.port()))), facet::landlock_abi() >= 4) << r.err;
        EXPECT_EQ(listener.connected(), facet::landlock_abi() < 4);
    }
}

// Real models (textures beside the model, assimp and facet's own readers) and the default scene give
// the same bytes in a sandboxed worker as in facet's own process, with 1 and 2 threads.
TEST(Sandbox, RendersUnderTheSandboxAreTheSameBytes) {
    std::vector<std::string> models = {""};  // the built-in scene
    if (fs::is_directory(facet_test::k_assimp_models)) {
        models.push_back((facet_test::k_assimp_models / "OBJ" / "spider.obj").string());
        models.push_back((facet_test::k_assimp_models / "glTF2" / "BoxTextured-glTF" / "BoxTextured.gltf").string());
    }
    if (const auto cgal = facet_test::cgal_meshes()) models.push_back((*cgal / "bunny00.off").string());
    const fs::path out = facet_test::test_temp_dir("facet_sandbox_same_bytes");
    for (const std::string& model : models)
        for (const std::string threads : {"1", "2"}) {
            SCOPED_TRACE(model + " threads " + threads);
            std::vector<CliRun> runs;
            for (bool isolated : {true, false}) {
                std::vector<std::string> args = {"render", "-o", (out / (isolated ? "a.png" : "b.png")).string(),
                                                 "--size", "96x64", "--threads", threads};
                if (!model.empty()) args.insert(args.begin() + 1, model);
                if (!isolated) args.push_back("--no-isolation");
                runs.push_back(run_facet(args));
                EXPECT_EQ(runs.back().exit_code, 0) << runs.back().err;
            }
            EXPECT_EQ(runs[0].err.find("warning"), std::string::npos) << runs[0].err;
            EXPECT_EQ(facet_test::read_file(out / "a.png"), facet_test::read_file(out / "b.png"));
        }
}

// The worker's default thread count is read under the sandbox (glibc counts the processors in /sys).
TEST(Sandbox, DefaultThreadCountIsUnchanged) {
    const Folders s = make_folders("threads");
    const CliRun r = run_facet({"render", s.model.string(), "--print-config"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.out, "\nthreads = " + std::to_string(std::max(1u, std::thread::hardware_concurrency())) + "\n"))
        << r.out;
    EXPECT_TRUE(contains(r.out, "\nsandbox = seccomp")) << r.out;
}

// Outputs in other folders (--depth-out) and outputs that are devices are written under the sandbox.
TEST(Sandbox, EveryOutputIsWritable) {
    const Folders s = make_folders("outputs");
    const CliRun r = run_facet({"render", s.model.string(), "-o", "/dev/null", "--depth-out", (s.other_dir / "depth.png").string(),
                                "--size", "32x24"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(s.other_dir / "depth.png"));
}

// load_model_isolated's child: the same rules. Its stderr is this process's, captured here.
TEST(Sandbox, IsolatedLoaderChildIsConfined) {
    const Folders s = make_folders("isolated");
    const Listener listener;
    const ScopedEnv hook("FACET_TEST_SANDBOX_PROBE", probes(s, listener.port(), true));
    testing::internal::CaptureStderr();
    const facet::Result<facet::LoadedModel> m = facet::load_model_isolated(s.model.string());
    const std::string err = testing::internal::GetCapturedStderr();
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_EQ(m->scene.triangle_count(), 12u);
    const bool landlock = facet::landlock_abi() > 0;
    EXPECT_TRUE(refused(probe_result(err, "socket:" + std::to_string(listener.port())))) << err;
    EXPECT_FALSE(listener.connected());
    EXPECT_TRUE(refused(probe_result(err, "exec"))) << err;
    EXPECT_TRUE(refused(probe_result(err, "fork"))) << err;
    EXPECT_EQ(refused(probe_result(err, "read:" + s.outside_file.string())), landlock) << err;
    EXPECT_EQ(probe_result(err, "read:" + s.model.string()), "allowed") << err;
    // It writes nothing at all: the result goes to a memory file opened before.
    EXPECT_EQ(refused(probe_result(err, "write:" + (s.out_dir / "w.txt").string())), landlock) << err;
}

}  // namespace
