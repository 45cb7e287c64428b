// The source of the object libraries that compile the test programs' shared precompiled
// headers (tests/CMakeLists.txt, nav_test_headers_*): it holds nothing of its own.
