#include "gl/state_report.h"

#include <epoxy/gl.h>

#include <sstream>

namespace subsplat::gl {
namespace {

class Report {
 public:
  void integers(const char* name, GLenum what, int count = 1) {
    GLint values[4] = {};
    glGetIntegerv(what, values);
    line(name, values, count);
  }
  void indexed(const char* name, GLenum what, GLuint index) {
    GLint value = 0;
    glGetIntegeri_v(what, index, &value);
    out_ << name << "[" << index << "]=" << value << "\n";
  }
  void indexed64(const char* name, GLenum what, GLuint index) {
    GLint64 value = 0;
    glGetInteger64i_v(what, index, &value);
    out_ << name << "[" << index << "]=" << value << "\n";
  }
  void floats(const char* name, GLenum what, int count = 1) {
    GLfloat values[4] = {};
    glGetFloatv(what, values);
    out_ << name << "=";
    for (int i = 0; i < count; ++i) out_ << (i ? "," : "") << values[i];
    out_ << "\n";
  }
  void booleans(const char* name, GLenum what, int count = 1) {
    GLboolean values[4] = {};
    glGetBooleanv(what, values);
    GLint asInt[4] = {values[0], values[1], values[2], values[3]};
    line(name, asInt, count);
  }
  void enabled(const char* name, GLenum what) { out_ << name << "=" << int(glIsEnabled(what)) << "\n"; }
  std::string text() const { return out_.str(); }

 private:
  void line(const char* name, const GLint* values, int count) {
    out_ << name << "=";
    for (int i = 0; i < count; ++i) out_ << (i ? "," : "") << values[i];
    out_ << "\n";
  }
  std::ostringstream out_;
};

}  // namespace

std::string describeState() {
  Report r;
  r.integers("draw_framebuffer", GL_DRAW_FRAMEBUFFER_BINDING);
  r.integers("read_framebuffer", GL_READ_FRAMEBUFFER_BINDING);
  r.integers("renderbuffer", GL_RENDERBUFFER_BINDING);
  r.integers("draw_buffer", GL_DRAW_BUFFER);
  r.integers("read_buffer", GL_READ_BUFFER);
  r.integers("program", GL_CURRENT_PROGRAM);
  r.integers("program_pipeline", GL_PROGRAM_PIPELINE_BINDING);
  r.integers("vertex_array", GL_VERTEX_ARRAY_BINDING);
  r.integers("element_array_buffer", GL_ELEMENT_ARRAY_BUFFER_BINDING);
  r.integers("array_buffer", GL_ARRAY_BUFFER_BINDING);
  r.integers("uniform_buffer", GL_UNIFORM_BUFFER_BINDING);
  r.integers("shader_storage_buffer", GL_SHADER_STORAGE_BUFFER_BINDING);
  r.integers("texture_buffer", GL_TEXTURE_BUFFER_BINDING);
  r.integers("pixel_pack_buffer", GL_PIXEL_PACK_BUFFER_BINDING);
  r.integers("pixel_unpack_buffer", GL_PIXEL_UNPACK_BUFFER_BINDING);
  r.integers("copy_read_buffer", GL_COPY_READ_BUFFER_BINDING);
  r.integers("copy_write_buffer", GL_COPY_WRITE_BUFFER_BINDING);
  r.integers("draw_indirect_buffer", GL_DRAW_INDIRECT_BUFFER_BINDING);
  r.integers("dispatch_indirect_buffer", GL_DISPATCH_INDIRECT_BUFFER_BINDING);
  r.integers("atomic_counter_buffer", GL_ATOMIC_COUNTER_BUFFER_BINDING);
  r.integers("transform_feedback_buffer", GL_TRANSFORM_FEEDBACK_BUFFER_BINDING);
  for (GLuint i = 0; i < 8; ++i) {
    r.indexed("uniform_buffer", GL_UNIFORM_BUFFER_BINDING, i);
    r.indexed64("uniform_buffer_start", GL_UNIFORM_BUFFER_START, i);
    r.indexed64("uniform_buffer_size", GL_UNIFORM_BUFFER_SIZE, i);
    r.indexed("shader_storage_buffer", GL_SHADER_STORAGE_BUFFER_BINDING, i);
    r.indexed64("shader_storage_buffer_start", GL_SHADER_STORAGE_BUFFER_START, i);
    r.indexed64("shader_storage_buffer_size", GL_SHADER_STORAGE_BUFFER_SIZE, i);
    r.indexed("image_name", GL_IMAGE_BINDING_NAME, i);
    r.indexed("image_level", GL_IMAGE_BINDING_LEVEL, i);
    r.indexed("image_layered", GL_IMAGE_BINDING_LAYERED, i);
    r.indexed("image_layer", GL_IMAGE_BINDING_LAYER, i);
    r.indexed("image_access", GL_IMAGE_BINDING_ACCESS, i);
    r.indexed("image_format", GL_IMAGE_BINDING_FORMAT, i);
  }
  GLint active = 0;
  glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
  r.integers("active_texture", GL_ACTIVE_TEXTURE);
  GLint units = 16;
  glGetIntegerv(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, &units);
  units = units < 32 ? units : 32;
  for (GLint unit = 0; unit < units; ++unit) {
    glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    const std::string u = "[" + std::to_string(unit) + "]";
    r.integers(("texture_2d" + u).c_str(), GL_TEXTURE_BINDING_2D);
    r.integers(("texture_2d_array" + u).c_str(), GL_TEXTURE_BINDING_2D_ARRAY);
    r.integers(("texture_3d" + u).c_str(), GL_TEXTURE_BINDING_3D);
    r.integers(("texture_cube" + u).c_str(), GL_TEXTURE_BINDING_CUBE_MAP);
    r.integers(("texture_buffer" + u).c_str(), GL_TEXTURE_BINDING_BUFFER);
    r.integers(("texture_1d" + u).c_str(), GL_TEXTURE_BINDING_1D);
    r.integers(("sampler" + u).c_str(), GL_SAMPLER_BINDING);
  }
  glActiveTexture(GLenum(active));
  r.integers("viewport", GL_VIEWPORT, 4);
  r.integers("scissor_box", GL_SCISSOR_BOX, 4);
  r.floats("depth_range", GL_DEPTH_RANGE, 2);
  r.integers("clip_origin", GL_CLIP_ORIGIN);
  r.integers("clip_depth_mode", GL_CLIP_DEPTH_MODE);
  for (const auto& [name, what] : std::initializer_list<std::pair<const char*, GLenum>>{
           {"pack_alignment", GL_PACK_ALIGNMENT}, {"unpack_alignment", GL_UNPACK_ALIGNMENT},
           {"pack_row_length", GL_PACK_ROW_LENGTH}, {"unpack_row_length", GL_UNPACK_ROW_LENGTH},
           {"pack_skip_rows", GL_PACK_SKIP_ROWS}, {"unpack_skip_rows", GL_UNPACK_SKIP_ROWS},
           {"pack_skip_pixels", GL_PACK_SKIP_PIXELS}, {"unpack_skip_pixels", GL_UNPACK_SKIP_PIXELS},
           {"pack_image_height", GL_PACK_IMAGE_HEIGHT}, {"unpack_image_height", GL_UNPACK_IMAGE_HEIGHT},
           {"pack_swap_bytes", GL_PACK_SWAP_BYTES}, {"unpack_swap_bytes", GL_UNPACK_SWAP_BYTES},
           {"blend_src_rgb", GL_BLEND_SRC_RGB}, {"blend_dst_rgb", GL_BLEND_DST_RGB},
           {"blend_src_alpha", GL_BLEND_SRC_ALPHA}, {"blend_dst_alpha", GL_BLEND_DST_ALPHA},
           {"blend_equation_rgb", GL_BLEND_EQUATION_RGB}, {"blend_equation_alpha", GL_BLEND_EQUATION_ALPHA},
           {"depth_func", GL_DEPTH_FUNC}, {"cull_face_mode", GL_CULL_FACE_MODE}, {"front_face", GL_FRONT_FACE},
           {"stencil_func", GL_STENCIL_FUNC}, {"stencil_ref", GL_STENCIL_REF},
           {"stencil_value_mask", GL_STENCIL_VALUE_MASK}, {"stencil_writemask", GL_STENCIL_WRITEMASK},
           {"stencil_fail", GL_STENCIL_FAIL}, {"stencil_pass_depth_pass", GL_STENCIL_PASS_DEPTH_PASS},
           {"stencil_pass_depth_fail", GL_STENCIL_PASS_DEPTH_FAIL}, {"provoking_vertex", GL_PROVOKING_VERTEX},
           {"patch_vertices", GL_PATCH_VERTICES}}) {
    r.integers(name, what);
  }
  r.integers("polygon_mode", GL_POLYGON_MODE, 1);
  r.booleans("depth_writemask", GL_DEPTH_WRITEMASK);
  r.booleans("color_writemask", GL_COLOR_WRITEMASK, 4);
  r.floats("color_clear_value", GL_COLOR_CLEAR_VALUE, 4);
  r.floats("depth_clear_value", GL_DEPTH_CLEAR_VALUE);
  r.integers("stencil_clear_value", GL_STENCIL_CLEAR_VALUE);
  r.floats("blend_color", GL_BLEND_COLOR, 4);
  r.floats("line_width", GL_LINE_WIDTH);
  r.floats("point_size", GL_POINT_SIZE);
  r.floats("polygon_offset_factor", GL_POLYGON_OFFSET_FACTOR);
  r.floats("polygon_offset_units", GL_POLYGON_OFFSET_UNITS);
  for (const auto& [name, what] : std::initializer_list<std::pair<const char*, GLenum>>{
           {"blend", GL_BLEND}, {"depth_test", GL_DEPTH_TEST}, {"cull_face", GL_CULL_FACE},
           {"scissor_test", GL_SCISSOR_TEST}, {"stencil_test", GL_STENCIL_TEST}, {"depth_clamp", GL_DEPTH_CLAMP},
           {"polygon_offset_fill", GL_POLYGON_OFFSET_FILL}, {"polygon_offset_line", GL_POLYGON_OFFSET_LINE},
           {"program_point_size", GL_PROGRAM_POINT_SIZE}, {"framebuffer_srgb", GL_FRAMEBUFFER_SRGB},
           {"multisample", GL_MULTISAMPLE}, {"sample_alpha_to_coverage", GL_SAMPLE_ALPHA_TO_COVERAGE},
           {"sample_coverage", GL_SAMPLE_COVERAGE}, {"dither", GL_DITHER}, {"line_smooth", GL_LINE_SMOOTH},
           {"primitive_restart", GL_PRIMITIVE_RESTART},
           {"primitive_restart_fixed_index", GL_PRIMITIVE_RESTART_FIXED_INDEX},
           {"rasterizer_discard", GL_RASTERIZER_DISCARD}, {"color_logic_op", GL_COLOR_LOGIC_OP},
           {"texture_cube_map_seamless", GL_TEXTURE_CUBE_MAP_SEAMLESS}}) {
    r.enabled(name, what);
  }
  return r.text();
}

}  // namespace subsplat::gl
