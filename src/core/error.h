#pragma once
// Error values for bad data (never for programmer mistakes, which are asserts).
// Exceptions never cross a library boundary: functions that can fail on input
// return an Error or a Result<T>.

#include <cassert>
#include <optional>
#include <string>
#include <utility>
#include <variant>

namespace mlod {

// An error message, or none. Converts to true when there IS an error.
class Error {
public:
  Error() = default;
  explicit Error(std::string message) : m_message(std::move(message)) { assert(!m_message.empty()); }

  explicit operator bool() const { return !m_message.empty(); }
  const std::string& message() const { return m_message; }

private:
  std::string m_message;
};

// Either a value or an Error with a message.
template <typename T>
class Result {
public:
  Result(T value) : m_state(std::move(value)) {}
  Result(Error error) : m_state(std::move(error)) { assert(std::get<Error>(m_state)); }

  bool ok() const { return std::holds_alternative<T>(m_state); }
  explicit operator bool() const { return ok(); }

  const T& value() const& { assert(ok()); return std::get<T>(m_state); }
  T& value() & { assert(ok()); return std::get<T>(m_state); }
  T&& value() && { assert(ok()); return std::get<T>(std::move(m_state)); }
  const T& operator*() const& { return value(); }
  T& operator*() & { return value(); }
  const T* operator->() const { return &value(); }
  T* operator->() { return &value(); }

  const Error& error() const { assert(!ok()); return std::get<Error>(m_state); }
  const std::string& message() const { return error().message(); }

private:
  std::variant<T, Error> m_state;
};

} // namespace mlod
