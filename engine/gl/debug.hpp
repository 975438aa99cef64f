#pragma once
// KHR_debug output: GL errors are logged with their message and counted, so a test can fail on
// any GL error (docs/testing.md).
namespace candela::gl {

void enable_debug_output();
int debug_error_count();
void reset_debug_error_count();

}  // namespace candela::gl
