// facet exec: the sandbox of processes that read untrusted files (facet/sandbox.hpp). seccomp through
// libseccomp; Landlock through its system calls (glibc has no wrappers), with the constants of its
// stable ABI spelled here, since Debian 12's kernel headers stop at ABI 2.
#include "facet/sandbox.hpp"

#include "facet/detail/module.hpp"
#include "exec/sanitized.hpp"

#if defined(__linux__)
#include <arpa/inet.h>
#include <link.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sched.h>
#include <seccomp.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>
#endif

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <thread>

namespace facet {

bool sanitizer_build() { return FACET_SANITIZED != 0; }

namespace {

// The folders of the shared libraries loaded in this process, each once.
std::vector<std::string> loaded_library_dirs() {
    std::vector<std::string> dirs;
#if defined(__linux__)
    dl_iterate_phdr(
        [](dl_phdr_info* info, std::size_t, void* data) {
            auto& out = *static_cast<std::vector<std::string>*>(data);
            if (!info->dlpi_name || info->dlpi_name[0] != '/') return 0;  // the program itself, the vDSO
            const std::string dir = std::filesystem::path(info->dlpi_name).parent_path().string();
            if (std::find(out.begin(), out.end(), dir) == out.end()) out.push_back(dir);
            return 0;
        },
        &dirs);
#endif
    return dirs;
}

}  // namespace

SandboxRules sandbox_rules_for_model(const std::string& model_path, const std::vector<std::string>& resource_dirs) {
    namespace fs = std::filesystem;
    SandboxRules rules;
    if (!model_path.empty()) {
        const fs::path folder = fs::path(model_path).parent_path();
        rules.read_dirs.push_back(folder.empty() ? "." : folder.string());
        rules.read_files.push_back(model_path);  // a link to a file elsewhere: that file
    }
    rules.read_dirs.insert(rules.read_dirs.end(), resource_dirs.begin(), resource_dirs.end());
    // glibc counts the processors for the default thread count here; libstdc++'s random_device
    // (temporary file names) falls back to /dev/urandom on processors without RDRAND.
    rules.read_dirs.push_back("/sys/devices/system/cpu");
    rules.read_files.push_back("/dev/urandom");
    // facet's modules (facet/detail/module.hpp), which a load opens when its file needs one (assimp's
    // formats, OBJ, glTF), and the shared libraries they need: the folders of the libraries the
    // process has loaded already, where the system's are, and the dynamic loader's cache.
    for (const std::string& dir : detail::module_dirs()) rules.read_dirs.push_back(dir);
    for (const std::string& dir : loaded_library_dirs()) rules.read_dirs.push_back(dir);
    rules.read_files.push_back("/etc/ld.so.cache");
    return rules;
}

#if defined(__linux__)
namespace {

// ---- Landlock (include/uapi/linux/landlock.h)

namespace landlock {
constexpr unsigned k_create_ruleset_version = 1u << 0;
constexpr int k_rule_path_beneath = 1;

constexpr std::uint64_t k_execute = 1ull << 0, k_write_file = 1ull << 1, k_read_file = 1ull << 2, k_read_dir = 1ull << 3,
                        k_remove_file = 1ull << 5, k_make_reg = 1ull << 8, k_truncate = 1ull << 14,
                        k_ioctl_dev = 1ull << 15;
constexpr std::uint64_t k_abi1_fs = (1ull << 13) - 1;  // execute .. make_sym
constexpr std::uint64_t k_refer = 1ull << 13;          // ABI 2
constexpr std::uint64_t k_file_rights = k_execute | k_write_file | k_read_file | k_truncate | k_ioctl_dev;
constexpr std::uint64_t k_net_bind_tcp = 1ull << 0, k_net_connect_tcp = 1ull << 1;                 // ABI 4
constexpr std::uint64_t k_scope_abstract_unix_socket = 1ull << 0, k_scope_signal = 1ull << 1;      // ABI 6

struct RulesetAttr {
    std::uint64_t handled_access_fs = 0;
    std::uint64_t handled_access_net = 0;
    std::uint64_t scoped = 0;
};

struct __attribute__((packed)) PathBeneathAttr {
    std::uint64_t allowed_access = 0;
    std::int32_t parent_fd = -1;
};

// The file system rights this ABI knows, which a ruleset must list as handled.
std::uint64_t handled_fs(int abi) {
    std::uint64_t fs = k_abi1_fs;
    if (abi >= 2) fs |= k_refer;
    if (abi >= 3) fs |= k_truncate;
    if (abi >= 5) fs |= k_ioctl_dev;
    return fs;
}

int create_ruleset(const RulesetAttr* attr, std::size_t size, unsigned flags) {
    return static_cast<int>(syscall(SYS_landlock_create_ruleset, attr, size, flags));
}
}  // namespace landlock

// Adds `rights` beneath `path` (a folder) or on it (a file); a path that does not exist is skipped:
// nothing beneath it is readable then, which is the safe side.
void allow(int ruleset, const std::string& path, std::uint64_t rights, std::uint64_t handled) {
    const int fd = open(path.c_str(), O_PATH | O_CLOEXEC);
    if (fd < 0) return;
    struct stat st {};
    if (fstat(fd, &st) == 0) {
        landlock::PathBeneathAttr rule;
        rule.allowed_access = rights & handled & (S_ISDIR(st.st_mode) ? ~0ull : landlock::k_file_rights);
        rule.parent_fd = fd;
        if (rule.allowed_access != 0) syscall(SYS_landlock_add_rule, ruleset, landlock::k_rule_path_beneath, &rule, 0);
    }
    close(fd);
}

// Returns the ABI applied, or 0 with `why` set.
int apply_landlock(const SandboxRules& rules, std::string& why) {
    const int abi = landlock_abi();
    if (abi <= 0) {
        why = "Landlock: not offered by this kernel";
        return 0;
    }
    landlock::RulesetAttr attr;
    attr.handled_access_fs = landlock::handled_fs(abi);
    if (abi >= 4) attr.handled_access_net = landlock::k_net_bind_tcp | landlock::k_net_connect_tcp;
    if (abi >= 6) attr.scoped = landlock::k_scope_abstract_unix_socket | landlock::k_scope_signal;
    const int ruleset = landlock::create_ruleset(&attr, sizeof attr, 0);
    if (ruleset < 0) {
        why = std::string("Landlock: cannot create a ruleset (") + std::strerror(errno) + ")";
        return 0;
    }
    const std::uint64_t fs = attr.handled_access_fs;
    const std::uint64_t read = landlock::k_read_file | landlock::k_read_dir;
    const std::uint64_t write = landlock::k_write_file | landlock::k_make_reg | landlock::k_remove_file | landlock::k_truncate;
    for (const std::string& p : rules.read_dirs) allow(ruleset, p, read, fs);
    for (const std::string& p : rules.read_files) allow(ruleset, p, landlock::k_read_file, fs);
    for (const std::string& p : rules.write_dirs) allow(ruleset, p, write, fs);
    for (const std::string& p : rules.write_files) allow(ruleset, p, landlock::k_write_file | landlock::k_truncate, fs);
    // The sanitizers' runtimes read the process's own maps and threads (LeakSanitizer at exit).
    if (sanitizer_build()) allow(ruleset, "/proc/self", read, fs);
    int applied = 0;
    if (prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) == 0 && syscall(SYS_landlock_restrict_self, ruleset, 0) == 0)
        applied = abi;
    else
        why = std::string("Landlock: cannot restrict the process (") + std::strerror(errno) + ")";
    close(ruleset);
    return applied;
}

// ---- seccomp

bool apply_seccomp(std::string& why) {
    scmp_filter_ctx ctx = seccomp_init(SCMP_ACT_ALLOW);
    if (!ctx) {
        why = "seccomp: cannot create a filter";
        return false;
    }
    const std::uint32_t refuse = SCMP_ACT_ERRNO(EPERM);
    bool ok = seccomp_attr_set(ctx, SCMP_FLTATR_CTL_TSYNC, 1) == 0;  // every thread, should there be others
    for (int call : {SCMP_SYS(socket), SCMP_SYS(socketpair), SCMP_SYS(connect), SCMP_SYS(bind), SCMP_SYS(listen),
                     SCMP_SYS(accept), SCMP_SYS(accept4),                        // networks
                     SCMP_SYS(execve), SCMP_SYS(execveat),                       // programs
                     SCMP_SYS(fork), SCMP_SYS(vfork),                            // processes
                     SCMP_SYS(process_vm_readv), SCMP_SYS(process_vm_writev),    // other processes' memory
                     SCMP_SYS(io_uring_setup), SCMP_SYS(io_uring_enter),         // system calls seccomp cannot see
                     SCMP_SYS(io_uring_register), SCMP_SYS(unshare), SCMP_SYS(setns), SCMP_SYS(bpf)})
        ok = ok && seccomp_rule_add(ctx, refuse, call, 0) == 0;
    // LeakSanitizer stops the threads from a tracer that shares the address space (clone with
    // CLONE_VM but not CLONE_THREAD) and attaches to them with ptrace.
    const std::uint64_t kept = sanitizer_build() ? CLONE_THREAD | CLONE_VM : CLONE_THREAD;
    if (!sanitizer_build()) ok = ok && seccomp_rule_add(ctx, refuse, SCMP_SYS(ptrace), 0) == 0;
    ok = ok && seccomp_rule_add(ctx, refuse, SCMP_SYS(clone), 1, SCMP_A0(SCMP_CMP_MASKED_EQ, kept, 0)) == 0;
    ok = ok && seccomp_rule_add(ctx, SCMP_ACT_ERRNO(ENOSYS), SCMP_SYS(clone3), 0) == 0;
    const int loaded = ok ? seccomp_load(ctx) : -1;
    seccomp_release(ctx);
    if (!ok) why = "seccomp: cannot build the filter";
    else if (loaded != 0) why = std::string("seccomp: not applied (") + std::strerror(-loaded) + ")";
    return ok && loaded == 0;
}

}  // namespace

int landlock_abi() {
    const int abi = landlock::create_ruleset(nullptr, 0, landlock::k_create_ruleset_version);
    return abi > 0 ? abi : 0;
}

SandboxStatus enter_sandbox(const SandboxRules& rules) {
    SandboxStatus status;
    std::string landlock_why, seccomp_why;
    if (rules.landlock) status.landlock_abi = apply_landlock(rules, landlock_why);
    if (rules.seccomp) status.seccomp = apply_seccomp(seccomp_why);
    for (const std::string* why : {&landlock_why, &seccomp_why})
        if (!why->empty()) status.missing += (status.missing.empty() ? "" : "; ") + *why;
    return status;
}

namespace {

// One probe of sandbox_test_probe: "" when allowed, else why not.
std::string probe(const std::string& action) {
    auto failed = [](const char* what) { return std::string(what) + ": " + std::strerror(errno); };
    const std::size_t colon = action.find(':');
    const std::string verb = action.substr(0, colon), arg = colon == std::string::npos ? "" : action.substr(colon + 1);
    if (verb == "socket") {
        const int s = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
        if (s < 0) return failed("socket");
        sockaddr_in to{};
        to.sin_family = AF_INET;
        to.sin_port = htons(static_cast<std::uint16_t>(std::atoi(arg.c_str())));
        to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        const bool connected = connect(s, reinterpret_cast<const sockaddr*>(&to), sizeof to) == 0;
        const std::string why = connected ? "" : failed("connect");
        close(s);
        return why;
    }
    if (verb == "exec") {
        execl("/bin/true", "true", static_cast<char*>(nullptr));
        return failed("execl");
    }
    if (verb == "fork") {
        const pid_t child = fork();
        if (child < 0) return failed("fork");
        if (child == 0) _exit(0);
        waitpid(child, nullptr, 0);
        return "";
    }
    if (verb == "thread") {
        try {
            std::thread([] {}).join();
        } catch (const std::exception& e) {
            return std::string("std::thread: ") + e.what();
        }
        return "";
    }
    if (verb == "read" || verb == "write") {
        const int fd = verb == "read" ? open(arg.c_str(), O_RDONLY | O_CLOEXEC) : open(arg.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
        if (fd < 0) return failed("open");
        close(fd);
        return "";
    }
    return "unknown probe";
}

}  // namespace

void sandbox_test_probe() {
    const char* spec = std::getenv("FACET_TEST_SANDBOX_PROBE");
    if (!spec || !*spec) return;
    const std::string all = spec;
    for (std::size_t at = 0; at <= all.size();) {
        const std::size_t end = std::min(all.find(';', at), all.size());
        const std::string action = all.substr(at, end - at);
        at = end + 1;
        if (action.empty()) continue;
        std::fflush(nullptr);  // before an exec or a fork
        const std::string why = probe(action);
        std::fprintf(stderr, "facet: sandbox probe %s: %s\n", action.c_str(), why.empty() ? "allowed" : ("refused (" + why + ")").c_str());
    }
}

#else

void sandbox_test_probe() {}

int landlock_abi() { return 0; }

SandboxStatus enter_sandbox(const SandboxRules&) {
    SandboxStatus status;
    status.missing = "no sandbox on this system";
    return status;
}

#endif

}  // namespace facet
