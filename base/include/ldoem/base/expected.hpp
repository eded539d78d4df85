// A value-or-error type shaped like C++23 std::expected, so that callers can switch to the
// standard one later without rewriting. Decoders, parsers and the driver return it; nothing in
// protocol/ throws.
#pragma once

#include <cassert>
#include <type_traits>
#include <utility>
#include <variant>

namespace ldoem::base {

template <class E>
class Unexpected {
 public:
  constexpr explicit Unexpected(E error) : error_(std::move(error)) {}
  constexpr const E& error() const& { return error_; }
  constexpr E& error() & { return error_; }

 private:
  E error_;
};

template <class E>
Unexpected(E) -> Unexpected<E>;

template <class T, class E>
class [[nodiscard]] Expected {
 public:
  using value_type = T;
  using error_type = E;

  template <class U = T, class = std::enable_if_t<std::is_constructible_v<T, U&&>>>
  constexpr Expected(U&& value) : state_(std::in_place_index<0>, std::forward<U>(value)) {}
  constexpr Expected(Unexpected<E> error) : state_(std::in_place_index<1>, std::move(error.error())) {}

  constexpr bool has_value() const { return state_.index() == 0; }
  constexpr explicit operator bool() const { return has_value(); }

  constexpr T& value() & { assert(has_value()); return std::get<0>(state_); }
  constexpr const T& value() const& { assert(has_value()); return std::get<0>(state_); }
  constexpr T&& value() && { assert(has_value()); return std::get<0>(std::move(state_)); }
  constexpr T& operator*() & { return value(); }
  constexpr const T& operator*() const& { return value(); }
  constexpr T* operator->() { return &value(); }
  constexpr const T* operator->() const { return &value(); }

  constexpr const E& error() const { assert(!has_value()); return std::get<1>(state_); }

  template <class U>
  constexpr T value_or(U&& fallback) const& {
    return has_value() ? value() : static_cast<T>(std::forward<U>(fallback));
  }

 private:
  std::variant<T, E> state_;
};

}  // namespace ldoem::base
