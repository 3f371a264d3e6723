// facet: confining a process that reads untrusted files, for worker processes such as those of
// `facet render` and `facet thumbs` and load_model_isolated's child. Defence in depth beneath the
// loaders' own rule (LoadOptions::resource_dirs): if a reader is made to misbehave, the kernel still
// refuses what the job never needs. Linux only; elsewhere enter_sandbox confines nothing.
//
//  - seccomp (a system-call filter, through libseccomp): no new sockets, no exec, no new processes
//    (threads stay allowed: fork, vfork and clone without CLONE_THREAD are refused), no ptrace,
//    io_uring, unshare or setns. A refused call fails with EPERM (clone3 with ENOSYS, so that glibc
//    creates threads with clone, whose flags the filter can see).
//  - Landlock, where the kernel offers it (Linux 5.13 and later, when enabled): files are read only
//    beneath `read_dirs` (and `read_files`) and written only beneath `write_dirs` (creating, writing,
//    renaming and removing regular files) and to `write_files`; with Landlock ABI 4 and later no TCP
//    connect or bind either, with ABI 6 and later no signals or abstract Unix sockets reaching
//    processes outside the sandbox.
// Each is applied if the kernel can; what it cannot is left out and said in the status, never an
// error. Call while the process has a single thread, before it reads untrusted input: the rules
// bind the calling thread and everything it starts afterwards, and cannot be lifted.
#pragma once

#include <string>
#include <vector>

#include "facet/api.hpp"

FACET_API_BEGIN
namespace facet {

struct SandboxRules {
    std::vector<std::string> read_dirs, read_files;    // readable, with everything beneath a folder
    std::vector<std::string> write_dirs, write_files;  // writable, as above
    bool seccomp = true;   // false: leave the system-call filter out
    bool landlock = true;  // false: leave the file and network rules out
};

// The rules for reading a model: its folder (and, if the model is a link to a file elsewhere, that
// file) and the resource folders (LoadOptions::resource_dirs), and what any job needs besides: the
// processor list (the default thread count) and /dev/urandom, and what opening facet's modules
// takes (their folders, those of the shared libraries loaded, the dynamic loader's cache: a load
// opens the assimp module when its file needs it). Add the write rules of the job.
SandboxRules sandbox_rules_for_model(const std::string& model_path, const std::vector<std::string>& resource_dirs);

struct SandboxStatus {
    bool seccomp = false;   // the system-call filter is in place
    int landlock_abi = 0;   // the Landlock ABI whose rules are in place; 0: none
    std::string missing;    // what was left out and why, empty when nothing was
};

SandboxStatus enter_sandbox(const SandboxRules& rules);

// The Landlock ABI this kernel offers (0: none), without changing anything.
int landlock_abi();

// TEST HOOK, for the sandbox's tests only: when FACET_TEST_SANDBOX_PROBE is set, tries each of its
// ';'-separated actions and prints on stderr "facet: sandbox probe ACTION: allowed" or "...: refused
// (reason)": "socket:PORT" (a TCP connection to 127.0.0.1:PORT), "exec" (/bin/true: if allowed, the
// process becomes it), "fork", "thread", "read:PATH", "write:PATH" (creates PATH). Without the
// variable (as always outside the tests) it does nothing. Called where a sandboxed job starts.
void sandbox_test_probe();

// True in AddressSanitizer and ThreadSanitizer builds, whose runtimes need more of the kernel: the
// filter then also lets clone share the address space (LeakSanitizer's tracer), and ptrace.
bool sanitizer_build();

}  // namespace facet
FACET_API_END
