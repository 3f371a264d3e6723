// facet command line: CLI11's App::add_option and App::add_flag without CLI11's quadratic check of
// the new option's names. CLI11 (2.1.2) compares each new option with every option its command
// already has, copying the other option's list of names for each comparison
// (detail::find_member takes it by value): for `facet render`'s ~50 options, 0.5 M of the parent
// process's 1.8 M instructions. These hand CLI11 an empty list to compare with and make the same
// check themselves on the names as they are, throwing the same error. Only main.cpp and
// options.cpp include this (CLI11 is slow to compile).
#pragma once

#include <CLI/CLI.hpp>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace facet::cli {
namespace detail {

// A command's options, protected in CLI::App, through a member pointer taken in a derived class.
struct AppOptions : CLI::App {
    static constexpr std::vector<CLI::Option_p> CLI::App::*list = &AppOptions::options_;
};

// CLI11's Option::matching_name where neither option ignores case or underscores (the case here),
// without its copies; CLI11's own otherwise.
inline const std::string* matching_name(const CLI::Option& a, const CLI::Option& b) {
    if (a.get_ignore_case() || a.get_ignore_underscore() || b.get_ignore_case() || b.get_ignore_underscore()) {
        const std::string& name = a.matching_name(b);
        return name.empty() ? nullptr : &name;
    }
    for (const std::string& s : a.get_snames())
        for (const std::string& t : b.get_snames())
            if (s == t) return &s;
    for (const std::string& l : a.get_lnames())
        for (const std::string& m : b.get_lnames())
            if (l == m) return &l;
    return nullptr;
}

// Calls `add` (which adds one option to `app`) with the command's other options set aside, then
// checks the new one's names against theirs and puts them back in their order, the new one last.
template <class Add>
CLI::Option* add_alone(CLI::App& app, Add&& add) {
    std::vector<CLI::Option_p>& options = app.*AppOptions::list;
    std::vector<CLI::Option_p> others = std::move(options);
    options.clear();
    CLI::Option* added = nullptr;
    try {
        added = add();
    } catch (...) {
        options = std::move(others);
        throw;
    }
    CLI::Option_p made = std::move(options.back());
    options = std::move(others);
    for (const CLI::Option_p& other : options)
        if (const std::string* name = matching_name(*other, *made))
            throw CLI::OptionAlreadyAdded("added option matched existing option name: " + *name);
    options.push_back(std::move(made));
    return added;
}

}  // namespace detail

// app.add_option(args...) and app.add_flag(args...), as CLI11 would add them.
template <class... Args>
CLI::Option* add_option(CLI::App& app, Args&&... args) {
    return detail::add_alone(app, [&] { return app.add_option(std::forward<Args>(args)...); });
}
template <class... Args>
CLI::Option* add_flag(CLI::App& app, Args&&... args) {
    return detail::add_alone(app, [&] { return app.add_flag(std::forward<Args>(args)...); });
}

}  // namespace facet::cli
