// Preview on GL ES 2: shaders/preview.{vert,frag}, the same maths as the GL ES 1.1 path.
#include "gles2_util.h"
#include "gl_clear.h"
#include "preview.h"

namespace {
const char kVertex[] =
#include "shaders/preview.vert.inc"
    ;
const char kFragment[] =
#include "shaders/preview.frag.inc"
    ;
}  // namespace

namespace srt {

sepal_result preview_gles2(const sepal_caps&, const sepal_preview_desc& d, const float light[3],
                         sepal_error* err) {
    static const char* const kAttributes[] = {"a_position", "a_normal", "a_uv", nullptr};
    // Compiled per call: the preview draws a handful of frames; asset paths compile once.
    const GLuint program = gles2_program("preview", kVertex, kFragment, kAttributes, err);
    if (!program) return err ? err->code : SEPAL_ERR_GL;
    clear_frame(d.clear_color[0], d.clear_color[1], d.clear_color[2], d.clear_color[3]);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glUseProgram(program);
    glUniformMatrix4fv(glGetUniformLocation(program, "u_model_view"), 1, GL_FALSE,
                       d.model_view);
    glUniformMatrix4fv(glGetUniformLocation(program, "u_projection"), 1, GL_FALSE,
                       d.projection);
    glUniform3fv(glGetUniformLocation(program, "u_light_dir"), 1, light);
    glUniform3fv(glGetUniformLocation(program, "u_base_color"), 1, d.base_color);
    glUniform1f(glGetUniformLocation(program, "u_ambient"), d.ambient);
    glUniform1i(glGetUniformLocation(program, "u_texture"), 0);

    GLuint tex = srt::preview_texture(d);

    const sepal_vertex* v = d.mesh->vertices;
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
    for (GLuint i = 0; i < 3; ++i) glEnableVertexAttribArray(i);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(sepal_vertex), v->position);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(sepal_vertex), v->normal);
    glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, sizeof(sepal_vertex), v->uv);
    glDrawElements(GL_TRIANGLES, d.mesh->index_count, GL_UNSIGNED_SHORT, d.mesh->indices);
    const sepal_result r = gl_check("preview_gles2 draw", err);

    for (GLuint i = 0; i < 3; ++i) glDisableVertexAttribArray(i);
    glUseProgram(0);
    glDeleteTextures(1, &tex);
    glDeleteProgram(program);
    return r != SEPAL_OK ? r : ok(err);
}

}  // namespace srt
