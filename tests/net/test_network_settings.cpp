// The network's settings from the environment (networkSettingsFromEnvironment, what the command
// line and the viewer use): PARALLAX_HTTP_TIMEOUT, PARALLAX_HTTP_RETRIES, PARALLAX_HTTP_CACHE_MB
// and PARALLAX_CA_FILE reach the client, the retries and the cache exactly; a value that is not
// a whole number in range is an error naming the variable. (Each test runs in a process of its
// own under ctest; the variables are cleared after each.)
#include "net/network.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace parallax {
namespace {

const char* const kVariables[] = {"PARALLAX_HTTP_TIMEOUT", "PARALLAX_HTTP_RETRIES",
                                  "PARALLAX_HTTP_CACHE_MB", "PARALLAX_CA_FILE"};

class NetworkSettingsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* name : kVariables) ::unsetenv(name);
  }
  void TearDown() override {
    for (const char* name : kVariables) ::unsetenv(name);
  }
};

TEST_F(NetworkSettingsTest, DefaultsWithoutTheVariables) {
  const NetworkSettings s = networkSettingsFromEnvironment();
  const NetworkSettings defaults;
  EXPECT_EQ(s.http.stall_timeout, defaults.http.stall_timeout);
  EXPECT_EQ(s.http.connect_timeout, defaults.http.connect_timeout);
  EXPECT_EQ(s.retry.max_attempts, defaults.retry.max_attempts);
  EXPECT_TRUE(s.use_cache);
  EXPECT_EQ(s.cache_bytes, 4ull << 30);
  EXPECT_EQ(s.http.ca_file, "");
}

TEST_F(NetworkSettingsTest, EachVariableReachesItsSetting) {
  ::setenv("PARALLAX_HTTP_TIMEOUT", "3", 1);
  ::setenv("PARALLAX_HTTP_RETRIES", "7", 1);
  ::setenv("PARALLAX_HTTP_CACHE_MB", "12", 1);
  ::setenv("PARALLAX_CA_FILE", "/etc/ssl/our-ca.pem", 1);
  const NetworkSettings s = networkSettingsFromEnvironment();
  EXPECT_EQ(s.http.stall_timeout, std::chrono::milliseconds(3000));
  // The connection's own timeout is never longer than the stall timeout.
  EXPECT_EQ(s.http.connect_timeout, std::chrono::milliseconds(3000));
  EXPECT_EQ(s.retry.max_attempts, 7);
  EXPECT_TRUE(s.use_cache);
  EXPECT_EQ(s.cache_bytes, 12ull << 20);
  EXPECT_EQ(s.http.ca_file, "/etc/ssl/our-ca.pem");
}

TEST_F(NetworkSettingsTest, ACacheOfZeroMegabytesIsNoCache) {
  ::setenv("PARALLAX_HTTP_CACHE_MB", "0", 1);
  EXPECT_FALSE(networkSettingsFromEnvironment().use_cache);
}

TEST_F(NetworkSettingsTest, AValueThatIsNotAWholeNumberInRangeIsNamed) {
  const std::pair<const char*, const char*> bad[] = {{"PARALLAX_HTTP_CACHE_MB", "lots"},
                                                     {"PARALLAX_HTTP_CACHE_MB", "-1"},
                                                     {"PARALLAX_HTTP_RETRIES", "0"},
                                                     {"PARALLAX_HTTP_RETRIES", "101"},
                                                     {"PARALLAX_HTTP_TIMEOUT", "2.5"}};
  for (const auto& [name, value] : bad) {
    SCOPED_TRACE(std::string(name) + "=" + value);
    ::setenv(name, value, 1);
    try {
      (void)networkSettingsFromEnvironment();
      ADD_FAILURE() << "accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(std::string(name) + "=" + value), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("expected a whole number"), std::string::npos)
          << e.what();
    }
    ::unsetenv(name);
  }
}

}  // namespace
}  // namespace parallax
