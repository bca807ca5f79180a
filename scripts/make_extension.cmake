# The Blender 4.2+ extension package: the staged add-on (build/scripts/addons/subsplat, native
# library included) with blender_manifest.toml at the root of a zip. Called by the dist target:
#   cmake -DADDON_DIR=... -DMANIFEST=... -DSTAGE=... -DOUTPUT=... -P scripts/make_extension.cmake
foreach(variable ADDON_DIR MANIFEST STAGE OUTPUT)
  if(NOT DEFINED ${variable})
    message(FATAL_ERROR "make_extension.cmake: ${variable} is not set")
  endif()
endforeach()
if(NOT EXISTS ${ADDON_DIR}/__init__.py OR NOT EXISTS ${ADDON_DIR}/libsubsplat.so)
  message(FATAL_ERROR "make_extension.cmake: ${ADDON_DIR} holds no built add-on (build the addon target)")
endif()
file(REMOVE_RECURSE ${STAGE})
file(COPY ${ADDON_DIR}/ DESTINATION ${STAGE} PATTERN "__pycache__" EXCLUDE PATTERN "*.pyc" EXCLUDE)
file(COPY ${MANIFEST} DESTINATION ${STAGE})
file(GLOB_RECURSE files RELATIVE ${STAGE} ${STAGE}/*)
list(SORT files)
file(REMOVE ${OUTPUT})
execute_process(COMMAND ${CMAKE_COMMAND} -E tar cf ${OUTPUT} --format=zip -- ${files}
                WORKING_DIRECTORY ${STAGE} RESULT_VARIABLE failed)
if(failed)
  message(FATAL_ERROR "make_extension.cmake: could not write ${OUTPUT}")
endif()
message(STATUS "Extension written to ${OUTPUT}")
