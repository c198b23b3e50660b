// The Catch2 main of ThreadSanitizer builds, compiled with the tests' instrumentation (the other
// builds link Debian's prebuilt libCatch2WithMain.a; tests/CMakeLists.txt says why).
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
