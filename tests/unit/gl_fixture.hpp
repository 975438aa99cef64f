#pragma once
// A GL context per test, on the backend the test is instantiated with; KHR_debug on, and any GL
// error during the test fails it.
#include <gtest/gtest.h>

#include <memory>

#include "gl/debug.hpp"
#include "platform/context.hpp"

namespace candela::test {

// `backend_of` picks the backend out of the test's parameter (the parameter itself for
// GlContextTest; a field of a larger case struct for other suites).
template <typename Param, Backend (*backend_of)(const Param&)>
class GlContextTestOf : public ::testing::TestWithParam<Param> {
protected:
    void SetUp() override {
        ContextOptions options;
        options.debug = true;
        ContextResult r = create_context(backend_of(this->GetParam()), options);
        ASSERT_TRUE(r.context) << r.error;
        context_ = std::move(r.context);
        gl::reset_debug_error_count();
    }
    void TearDown() override {
        if (context_) EXPECT_EQ(gl::debug_error_count(), 0) << "GL errors during the test";
    }
    std::unique_ptr<Context> context_;
};

inline Backend backend_itself(const Backend& b) { return b; }
using GlContextTest = GlContextTestOf<Backend, backend_itself>;

inline std::string backend_name(const ::testing::TestParamInfo<Backend>& info) { return to_string(info.param); }

}  // namespace candela::test
