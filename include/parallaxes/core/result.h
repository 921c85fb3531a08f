// Errors are values until the program's edge (DESIGN.md): library code returns
// Result<T>; tools/ prints the message and exits non-zero.
#pragma once

#include <new>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>

namespace px {

struct Error {
    std::string message;  // what went wrong, with context: file, field, line, GL log
};

inline Error make_error(std::string message) { return Error{std::move(message)}; }

template <typename T>
class [[nodiscard]] Result {
public:
    Result(T value) : v_(std::move(value)) {}
    Result(Error error) : v_(std::move(error)) {}

    bool ok() const { return std::holds_alternative<T>(v_); }
    explicit operator bool() const { return ok(); }

    T& value() & { return std::get<T>(v_); }
    const T& value() const& { return std::get<T>(v_); }
    T&& value() && { return std::get<T>(std::move(v_)); }
    T* operator->() { return &std::get<T>(v_); }
    const T* operator->() const { return &std::get<T>(v_); }
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }

    const Error& error() const { return std::get<Error>(v_); }

private:
    std::variant<T, Error> v_;
};

// Result<void>: success or an error.
class [[nodiscard]] Status {
public:
    Status() = default;
    Status(Error error) : error_(std::move(error)) {}
    bool ok() const { return !error_.has_value(); }
    explicit operator bool() const { return ok(); }
    const Error& error() const { return *error_; }

private:
    std::optional<Error> error_;
};

// Prefix an error message with context ("scene.json: " + message).
inline Error with_context(const std::string& context, const Error& e) {
    return Error{context + ": " + e.message};
}

// Runs f() and turns an allocation failure (std::bad_alloc, or the
// std::length_error of a size no container can hold) into an error naming
// `what`, at the library's edge, so a host app gets a message and keeps
// running. The limits of core/limits.h keep this the last resort.
template <typename F>
auto out_of_memory_is_an_error(const std::string& what, F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const std::bad_alloc&) {
        return Error{what + ": out of memory"};
    } catch (const std::length_error&) {
        return Error{what + ": out of memory (a size past what a container can hold)"};
    }
}

}  // namespace px
