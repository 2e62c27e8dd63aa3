// The translation unit that flsd_test_torch_pch makes libtorch's precompiled header with, at the
// tests' optimisation level (cmake/FlsdTest.cmake); the tests that include libtorch reuse it.
