// SPDX-License-Identifier: Apache-2.0
// Test module: a shared object that exports a function, but not vdbmap_plugin_info_v1.
extern "C" __attribute__((visibility("default"))) int vdbmap_test_not_a_plugin(void) { return 42; }
