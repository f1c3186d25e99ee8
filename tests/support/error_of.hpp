#pragma once
// The message of the mgelastic::Error a call throws, for tests of error reporting.
#include <gtest/gtest.h>

#include <string>

#include "mgelastic/core/error.hpp"

namespace mgelastic::test {

// Runs `call` and returns the Error's message; fails the test when nothing is thrown.
template <class Call>
std::string error_of(Call call) {
  try {
    call();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no mgelastic::Error thrown";
  return {};
}

}  // namespace mgelastic::test
