// Checks that a call throws an exception of a given type whose message says the right thing,
// built on GoogleMock's exception matchers:
//
//   EXPECT_THAT([&] { ReadRig(path); }, ThrowsWith<std::runtime_error>("invalid JSON"));
//   EXPECT_THAT([&] { Match(a, b); }, ThrowsWith<std::invalid_argument>("cam1", "000001"));  // both
//   EXPECT_THAT([&] { ValidateScene(s); }, ThrowsExactly<std::invalid_argument>("x.glb: mesh 0: ..."));
//   EXPECT_THAT([&] { LoadGltf(path); }, ThrowsNaming<std::runtime_error>(path, "vertex 2 is not finite"));
//
// The type may be a base class (std::runtime_error also matches its subclasses). A failure prints
// what the call did instead: returned normally, threw another type, or threw this message. Write
// the call inside the lambda: the matcher runs it once.
#pragma once

#include <string>

#include <gmock/gmock.h>

namespace rigsim {

// Throws E with `part` (and each of `more`) somewhere in its message.
template <typename E = std::exception, typename... More>
auto ThrowsWith(const std::string& part, const More&... more) {
  return ::testing::ThrowsMessage<E>(::testing::AllOf(::testing::HasSubstr(part), ::testing::HasSubstr(std::string(more))...));
}

// Throws E with exactly `message`.
template <typename E = std::exception>
auto ThrowsExactly(const std::string& message) {
  return ::testing::ThrowsMessage<E>(::testing::StrEq(message));
}

// Throws E whose message starts with the file (the rule for errors at I/O boundaries: the file,
// then the reason; a std::filesystem::path converts) and contains `part`.
template <typename E = std::exception>
auto ThrowsNaming(const std::string& file, const std::string& part) {
  return ::testing::ThrowsMessage<E>(::testing::AllOf(::testing::StartsWith(file), ::testing::HasSubstr(part)));
}

// The message of the E that `call` throws, or "" when it returns; for tests that look at one
// message in several ways, or whose "no error" is a result (a validator that accepts).
template <typename E = std::exception, typename Call>
std::string ErrorMessage(Call&& call) {
  try {
    call();
  } catch (const E& e) {
    return e.what();
  }
  return "";
}

}  // namespace rigsim
