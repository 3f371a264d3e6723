// facet's modules (facet/detail/module.hpp): opened from the build tree, a missing one named in the
// error, the command line not linked with what a module carries, and libfacet's list of assimp's
// extensions (io/assimp_module.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include <assimp/Importer.hpp>

#include "facet/detail/module.hpp"
#include "io/assimp_import.hpp"
#include "io/assimp_module.hpp"
#include "support/paths.hpp"

namespace {

using facet::detail::module_symbol;

TEST(Modules, AMissingModuleIsAnErrorNamingIt) {
    std::string why;
    EXPECT_EQ(module_symbol("libfacet_no_such_module.so", "anything", why), nullptr);
    EXPECT_NE(why.find("libfacet_no_such_module.so"), std::string::npos) << why;
}

TEST(Modules, TheAssimpModuleOpensAndGivesItsTable) {
    std::string why;
    using Entry = const facet::io_detail::AssimpModule* (*)();
    const auto entry = reinterpret_cast<Entry>(
        module_symbol(facet::io_detail::k_assimp_module, facet::io_detail::k_assimp_module_entry, why));
    ASSERT_NE(entry, nullptr) << why;
    const facet::io_detail::AssimpModule* table = entry();
    ASSERT_NE(table, nullptr);
    EXPECT_NE(table->load_with_assimp, nullptr);
    EXPECT_NE(table->load_own_scene, nullptr);
}

// The list libfacet keeps (made at build time) answers as assimp's importers do.
TEST(Modules, TheBuiltExtensionListIsAssimps) {
    const Assimp::Importer importer;
    std::string list;
    importer.GetExtensionList(list);
    int listed = 0;
    for (std::size_t at = 0; at < list.size();) {
        const std::size_t end = std::min(list.find(';', at), list.size());
        const std::string pattern = list.substr(at, end - at);
        at = end + 1;
        if (pattern.rfind("*.", 0) != 0) continue;
        EXPECT_TRUE(facet::io_detail::assimp_reads_extension(pattern.substr(2))) << pattern;
        ++listed;
    }
    EXPECT_GT(listed, 40);
    for (const char* ext : {"obj", "gltf", "glb", "fbx", "dae", "off", "png", "txt", "xyz", "", "objx", "ob"})
        EXPECT_EQ(facet::io_detail::assimp_reads_extension(ext), importer.IsExtensionSupported(std::string(".") + ext)) << ext;
}

#if FACET_TEST_HAS_EXR_MODULE
TEST(Modules, TheOpenExrWriterOpensOnceAndOtherSymbolsAreRefused) {
    std::string why;
    void* write = module_symbol("libfacet_exr.so", "facet_exr_write_v1", why);
    ASSERT_NE(write, nullptr) << why;
    EXPECT_EQ(module_symbol("libfacet_exr.so", "facet_exr_write_v1", why), write);
    EXPECT_EQ(module_symbol("libfacet_exr.so", "facet_exr_write_v0", why), nullptr);
    EXPECT_NE(why.find("facet_exr_write_v0"), std::string::npos) << why;
}

// The point of the modules: `facet` itself does not need assimp's or OpenEXR's libraries to start.
TEST(Modules, TheCommandLineLinksNeitherAssimpNorOpenExr) {
    const std::string command = std::string("objdump -p '") + facet_test::k_binary_dir + "/bin/facet' 2>&1";
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
    ASSERT_TRUE(pipe);
    std::string out;
    char buffer[4096];
    for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe.get())) > 0;) out.append(buffer, n);
    ASSERT_NE(out.find("NEEDED"), std::string::npos) << out.substr(0, 300);
    EXPECT_EQ(out.find("OpenEXR"), std::string::npos);
    EXPECT_EQ(out.find("libIex"), std::string::npos);
    EXPECT_EQ(out.find("libassimp"), std::string::npos);
    EXPECT_EQ(out.find("libdraco"), std::string::npos);
}
#endif

}  // namespace
