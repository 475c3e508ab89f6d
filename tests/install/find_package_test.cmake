# ctest: Install.FindPackageBuildsAndRunsTheExample. Installs the build into a temporary prefix, builds
# examples/ as a project of its own against it (find_package(spheremap)), and maps the example mesh.
# Variables: BUILD_DIR, SOURCE_DIR, WORK_DIR, GENERATOR, CXX_COMPILER, LIBDIR (CMAKE_INSTALL_LIBDIR).
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "failed (${code}): ${ARGN}\n${out}")
  endif()
endfunction()

run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix)
set(package ${LIBDIR}/cmake/spheremap)
foreach(installed bin/spheremap include/spheremap/pipeline/map_job.hpp ${LIBDIR}/libspheremap.a
        ${LIBDIR}/libspheremap_render.a ${package}/spheremapConfig.cmake ${package}/spheremapConfigVersion.cmake
        ${package}/spheremapTargets.cmake)
  if(NOT EXISTS ${WORK_DIR}/prefix/${installed})
    message(FATAL_ERROR "not installed: ${installed}")
  endif()
endforeach()
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples -B ${WORK_DIR}/build -G ${GENERATOR}
    -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${WORK_DIR}/build/map_mesh ${SOURCE_DIR}/examples/dumbbell.ply ${WORK_DIR}/sphere.ply)
if(NOT EXISTS ${WORK_DIR}/sphere.ply)
  message(FATAL_ERROR "the example wrote no sphere.ply")
endif()
file(REMOVE_RECURSE ${WORK_DIR})
