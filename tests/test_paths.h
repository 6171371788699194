// Where a test executable finds the project: the source folder, its module's testdata folder and
// the proxygrasp command. The build generates their definitions for each test executable
// (proxygrasp_tests in cmake/ProxygraspHelpers.cmake), so that no test file's compile line holds
// the clone's folder.
#pragma once

namespace pg::test {

/// The project's source folder, absolute.
const char* SourceDir();
/// tests/<module>/testdata of the executable's module, absolute.
const char* TestDataDir();
/// The built proxygrasp command, absolute.
const char* ProxygraspBin();

}  // namespace pg::test
