// facet: errors. API misuse and bad input are reported as an Error naming what was wrong (and the
// file, for I/O); fallible operations return Result<T>, which holds either a value or an Error.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <variant>

#include "facet/api.hpp"

FACET_API_BEGIN
namespace facet {

enum class ErrorCode {
    invalid_argument,  // an API call was given a value it cannot use (size 0, bad index, ...)
    io,                // a file could not be opened, read or written
    bad_format,        // a file's bytes are not a valid instance of its format
    unsupported,       // a valid file uses something facet does not handle
    limit_exceeded,    // the input is larger than a configured limit
};

const char* to_string(ErrorCode code);

struct Error {
    ErrorCode code = ErrorCode::invalid_argument;
    std::string message;  // complete sentence for a user: names the file and the problem
};

// Thrown by library calls that have no Result to return (constructors, draw) on invalid arguments.
class FacetError : public std::runtime_error {
public:
    explicit FacetError(Error e) : std::runtime_error(e.message), error_(std::move(e)) {}
    const Error& error() const { return error_; }

private:
    Error error_;
};

template <class T>
class [[nodiscard]] Result {
public:
    Result(T value) : v_(std::move(value)) {}
    Result(Error e) : v_(std::move(e)) {}
    bool ok() const { return v_.index() == 0; }
    explicit operator bool() const { return ok(); }
    T& value() & { return std::get<0>(v_); }
    const T& value() const& { return std::get<0>(v_); }
    T&& value() && { return std::get<0>(std::move(v_)); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }
    const Error& error() const { return std::get<1>(v_); }

private:
    std::variant<T, Error> v_;
};

struct Ok {};  // the value of a Result that carries no data
using Status = Result<Ok>;

}  // namespace facet
FACET_API_END
