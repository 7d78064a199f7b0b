// Expectations about errors shared by the bad-input tests.
#pragma once

#include "clraster/clraster.hpp"

#include <gtest/gtest.h>

#include <string>
#include <string_view>
#include <typeinfo>
#include <vector>

namespace clraster::test {

// Runs `action` and checks that it throws an `Exception` whose message is one line mentioning
// every one of `subjects`.
template <typename Exception = InvalidArgument, typename Action>
::testing::AssertionResult throws(Action&& action, const std::vector<std::string_view>& subjects) {
  try {
    action();
  } catch (const Exception& error) {
    const std::string_view message = error.what();
    if (message.find('\n') != std::string_view::npos) {
      return ::testing::AssertionFailure() << "message is not one line: '" << message << "'";
    }
    for (std::string_view subject : subjects) {
      if (message.find(subject) == std::string_view::npos) {
        return ::testing::AssertionFailure() << "message '" << message << "' does not mention '" << subject << "'";
      }
    }
    return ::testing::AssertionSuccess();
  } catch (const std::exception& error) {
    return ::testing::AssertionFailure() << "threw " << typeid(error).name() << " instead of "
                                         << typeid(Exception).name() << ": " << error.what();
  }
  return ::testing::AssertionFailure() << "did not throw";
}

}  // namespace clraster::test
