// facet's modules (facet/detail/module.hpp): opened from the build tree, a missing one named in the
// error, and the command line not linked with what a module carries.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>

#include "facet/detail/module.hpp"

namespace {

using facet::detail::module_symbol;

TEST(Modules, AMissingModuleIsAnErrorNamingIt) {
    std::string why;
    EXPECT_EQ(module_symbol("libfacet_no_such_module.so", "anything", why), nullptr);
    EXPECT_NE(why.find("libfacet_no_such_module.so"), std::string::npos) << why;
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

// The point of the module: `facet` itself does not need OpenEXR's libraries to start.
TEST(Modules, TheCommandLineDoesNotLinkOpenExr) {
    const std::string command = "objdump -p '" FACET_BINARY_DIR "/bin/facet' 2>&1";
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
    ASSERT_TRUE(pipe);
    std::string out;
    char buffer[4096];
    for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe.get())) > 0;) out.append(buffer, n);
    ASSERT_NE(out.find("NEEDED"), std::string::npos) << out.substr(0, 300);
    EXPECT_EQ(out.find("OpenEXR"), std::string::npos);
    EXPECT_EQ(out.find("libIex"), std::string::npos);
}
#endif

}  // namespace
