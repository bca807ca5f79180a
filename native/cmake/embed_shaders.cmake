# Writes a C++ source holding every shader file as a raw string, so the
# library never reads files at run time. Called with -DOUTPUT= -DSHADERS=a;b;c
string(REPLACE "|" ";" SHADERS "${SHADERS}")
set(body "// Generated from native/shaders by embed_shaders.cmake. Do not edit.\n#include \"gl/shader_sources.h\"\n#include <cstring>\n\nnamespace subsplat::gl {\nnamespace {\nstruct Entry { const char* name; const char* source; };\nconst Entry kShaders[] = {\n")
foreach(path ${SHADERS})
  get_filename_component(name ${path} NAME)
  file(READ ${path} text)
  set(body "${body}  {\"${name}\", R\"subsplat_glsl(${text})subsplat_glsl\"},\n")
endforeach()
set(body "${body}};\n}  // namespace\n\nconst char* shaderSource(const std::string& name) {\n  for (const Entry& e : kShaders)\n    if (name == e.name) return e.source;\n  return nullptr;\n}\n}  // namespace subsplat::gl\n")
file(WRITE ${OUTPUT}.tmp "${body}")
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different ${OUTPUT}.tmp ${OUTPUT})
