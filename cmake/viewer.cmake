# The offline viewer (index.html): three.js and esbuild from viewer/package-lock.json, installed with
# `npm ci` into the build tree, bundle the page, which becomes a generated C++ source of the render library.
# Included at the end of CMakeLists.txt, after the library and test targets exist.

find_program(SPHEREMAP_NODE_EXECUTABLE NAMES node nodejs)
find_program(SPHEREMAP_NPM_EXECUTABLE NAMES npm)
if(NOT SPHEREMAP_NODE_EXECUTABLE OR NOT SPHEREMAP_NPM_EXECUTABLE)
  message(FATAL_ERROR
    "spheremap's viewer (index.html) is built with Node.js and npm, and they were not found on the PATH.\n"
    "Fix: run scripts/install-deps.sh (it installs Debian's nodejs and npm when npm is missing), "
    "or install Node.js >= 20 with npm, then configure again.")
endif()

set(SPHEREMAP_VIEWER_SOURCE_DIR ${CMAKE_SOURCE_DIR}/viewer)
set(SPHEREMAP_VIEWER_BUILD_DIR ${CMAKE_BINARY_DIR}/viewer)
set(SPHEREMAP_VIEWER_NODE_MODULES ${SPHEREMAP_VIEWER_BUILD_DIR}/node_modules)
set(_viewer_npm_stamp ${SPHEREMAP_VIEWER_BUILD_DIR}/npm-ci.stamp)
set(_viewer_page_cpp ${CMAKE_BINARY_DIR}/generated/viewer_page.cpp)

# npm ci runs again only when package.json or the lock file changes. No install scripts (none is needed:
# esbuild finds its binary in its platform package) and never a browser download.
add_custom_command(
  OUTPUT ${_viewer_npm_stamp}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${SPHEREMAP_VIEWER_BUILD_DIR}
  COMMAND ${CMAKE_COMMAND} -E copy_if_different ${SPHEREMAP_VIEWER_SOURCE_DIR}/package.json
          ${SPHEREMAP_VIEWER_SOURCE_DIR}/package-lock.json ${SPHEREMAP_VIEWER_BUILD_DIR}
  COMMAND ${CMAKE_COMMAND} -E env PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm_config_update_notifier=false
          ${SPHEREMAP_NPM_EXECUTABLE} ci --ignore-scripts --no-audit --no-fund --loglevel=error
  COMMAND ${CMAKE_COMMAND} -E touch ${_viewer_npm_stamp}
  WORKING_DIRECTORY ${SPHEREMAP_VIEWER_BUILD_DIR}
  DEPENDS ${SPHEREMAP_VIEWER_SOURCE_DIR}/package.json ${SPHEREMAP_VIEWER_SOURCE_DIR}/package-lock.json
  COMMENT "viewer: npm ci (three.js, esbuild, playwright-core from viewer/package-lock.json)"
  VERBATIM)

# The bundle and the page; build.mjs writes a depfile naming every script it bundled.
add_custom_command(
  OUTPUT ${_viewer_page_cpp}
  COMMAND ${SPHEREMAP_NODE_EXECUTABLE} ${SPHEREMAP_VIEWER_SOURCE_DIR}/build.mjs
          --node-modules ${SPHEREMAP_VIEWER_NODE_MODULES} --out ${_viewer_page_cpp}
          --depfile ${_viewer_page_cpp}.d
  DEPENDS ${_viewer_npm_stamp} ${SPHEREMAP_VIEWER_SOURCE_DIR}/build.mjs ${SPHEREMAP_VIEWER_SOURCE_DIR}/src/page.html
  DEPFILE ${_viewer_page_cpp}.d
  COMMENT "viewer: bundling viewer/src into the page"
  VERBATIM)

# The render library once it is its own target, the core library until then.
if(TARGET spheremap_render)
  set(_viewer_target spheremap_render)
else()
  set(_viewer_target spheremap)
endif()
target_sources(${_viewer_target} PRIVATE ${_viewer_page_cpp})
set_source_files_properties(${_viewer_page_cpp} PROPERTIES INCLUDE_DIRECTORIES ${CMAKE_SOURCE_DIR}/src/render)
target_link_libraries(${_viewer_target} PRIVATE ZLIB::ZLIB)

if(SPHEREMAP_BUILD_TESTS)
  # The page's plain functions (colour rule, residue queries, orientation) under node's test runner.
  add_test(NAME ViewerScripts COMMAND ${SPHEREMAP_NODE_EXECUTABLE} --test ${SPHEREMAP_VIEWER_SOURCE_DIR}/test/
           WORKING_DIRECTORY ${SPHEREMAP_VIEWER_SOURCE_DIR})
  set_tests_properties(ViewerScripts PROPERTIES LABELS unit)
endif()

if(TARGET spheremap_tests)
  # The browser test drives Chromium through playwright-core from the same node_modules.
  target_compile_definitions(spheremap_tests PRIVATE
    SPHEREMAP_NODE_EXECUTABLE="${SPHEREMAP_NODE_EXECUTABLE}"
    SPHEREMAP_VIEWER_NODE_MODULES="${SPHEREMAP_VIEWER_NODE_MODULES}"
    SPHEREMAP_VIEWER_BROWSER_SCRIPT="${CMAKE_SOURCE_DIR}/tests/render/viewer_browser_test.mjs"
    SPHEREMAP_VIEWER_TEST_OUTPUT_DIR="${CMAKE_BINARY_DIR}/viewer-test")
endif()
