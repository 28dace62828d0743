// Prints the error ledger (worst error per check and family, collected by test_support.hpp) after the tests ran.
// Set ARIES_TEST_QUIET_LEDGER=1 to silence it.
#include "test_support.hpp"

#include <cstdio>
#include <cstdlib>

namespace {

class LedgerPrinter : public ::testing::Environment {
 public:
  void TearDown() override {
    const auto &w = aries::test::ErrorLedger::instance().worst();
    if (w.empty() || std::getenv("ARIES_TEST_QUIET_LEDGER")) return;
    std::printf("\n[ledger] worst observed error per check / family (%zu entries)\n", w.size());
    for (const auto &[key, err] : w) std::printf("[ledger] %-64s %.3e\n", key.c_str(), err);
  }
};

[[maybe_unused]] ::testing::Environment *const kLedger = ::testing::AddGlobalTestEnvironment(new LedgerPrinter);

}  // namespace
