// apps/cli/add_option.hpp: options added without CLI11's own comparison with every earlier option
// keep CLI11's rules. A name already taken (short or long, by any earlier option, the help flag
// too) is refused with CLI11's own error and message, the command left as it was; the options keep
// their order, and the command line fills them.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "add_option.hpp"

namespace {

using facet::cli::add_flag;
using facet::cli::add_option;

std::vector<std::string> names(const CLI::App& app) {
    std::vector<std::string> out;
    for (const CLI::Option* o : app.get_options()) out.push_back(o->get_name());
    return out;
}

// CLI11's message for adding `name` to a command that has `taken`, or "" when it takes it.
template <class Add>
std::string refusal(Add&& add) {
    try {
        add();
    } catch (const CLI::OptionAlreadyAdded& e) {
        return e.what();
    }
    return "";
}

TEST(CliAddOption, RefusesANameAlreadyTakenAsCli11Does) {
    int size = 0, other = 0;
    bool flag = false;
    CLI::App ours{"ours"}, cli11{"cli11"};
    add_option(ours, "-s,--size", size, "");
    add_flag(ours, "--flag", flag, "");
    cli11.add_option("-s,--size", size, "");
    cli11.add_flag("--flag", flag, "");
    const std::vector<std::string> before = names(ours);
    for (const char* taken : {"--size", "-s", "-x,--size", "-s,--width", "--flag", "-h", "--help"}) {
        const std::string expected = refusal([&] { cli11.add_option(taken, other, ""); });
        ASSERT_FALSE(expected.empty()) << taken;
        EXPECT_EQ(refusal([&] { add_option(ours, taken, other, ""); }), expected) << taken;
        EXPECT_EQ(refusal([&] { add_flag(ours, taken, flag, ""); }), expected) << taken;
        EXPECT_EQ(names(ours), before) << taken;
    }
    // Another error of CLI11's (a flag cannot be positional) leaves the command as it was too.
    EXPECT_THROW(add_flag(ours, "positional", flag, ""), CLI::IncorrectConstruction);
    EXPECT_EQ(names(ours), before);
}

TEST(CliAddOption, KeepsTheOrderAndParses) {
    CLI::App app{"test"};
    int one = 0;
    bool two = false;
    std::string three;
    add_option(app, "--one", one, "");
    add_flag(app, "-t,--two", two, "");
    add_option(app, "three", three, "");
    EXPECT_EQ(names(app), (std::vector<std::string>{"--help", "--one", "--two", "three"}));
    app.parse("--one 5 -t x", false);
    EXPECT_EQ(one, 5);
    EXPECT_TRUE(two);
    EXPECT_EQ(three, "x");
}

}  // namespace
