// The test executables' main: GoogleTest's own (gtest_main), after the
// allocator setting every front end makes at its start
// (common/allocator.h KeepFreedMemory), so that the fits a test runs use
// memory as the tools' do.
#include <gtest/gtest.h>

#include "common/allocator.h"

int main(int argc, char** argv) {
  axis::KeepFreedMemory();
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
