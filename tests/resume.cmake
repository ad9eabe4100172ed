# SPDX-License-Identifier: Apache-2.0
# ResumeTest (issue 36) runs the built `vdbmap` with the texture and semantic plugins.
if(TARGET ResumeTest AND TARGET vdbmap_app)
    add_dependencies(ResumeTest vdbmap_app vdbmap_plugin_texture vdbmap_plugin_semantic)
endif()
