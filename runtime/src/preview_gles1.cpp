// Preview on GL ES 1.1 fixed function: glLight Gouraud shading x texture (GL_MODULATE).
#include <GLES/gl.h>
#include "gl_clear.h"

#include "preview.h"

namespace srt {

sepal_result preview_gles1(const sepal_caps&, const sepal_preview_desc& d, const float light[3],
                         sepal_error* err) {
    clear_frame(d.clear_color[0], d.clear_color[1], d.clear_color[2], d.clear_color[3]);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);

    glMatrixMode(GL_PROJECTION);
    glLoadMatrixf(d.projection);
    glMatrixMode(GL_MODELVIEW);
    // The light is given in eye space: set its position under an identity modelview.
    glLoadIdentity();
    const GLfloat position[4] = {light[0], light[1], light[2], 0.0f};
    const GLfloat zero[4] = {0, 0, 0, 1}, one[4] = {1, 1, 1, 1};
    const GLfloat scene_ambient[4] = {d.ambient, d.ambient, d.ambient, 1.0f};
    const GLfloat base[4] = {d.base_color[0], d.base_color[1], d.base_color[2], 1.0f};
    glLightfv(GL_LIGHT0, GL_POSITION, position);
    glLightfv(GL_LIGHT0, GL_AMBIENT, zero);
    glLightfv(GL_LIGHT0, GL_DIFFUSE, one);
    glLightfv(GL_LIGHT0, GL_SPECULAR, zero);
    glLightModelfv(GL_LIGHT_MODEL_AMBIENT, scene_ambient);
    glMaterialfv(GL_FRONT_AND_BACK, GL_AMBIENT, base);
    glMaterialfv(GL_FRONT_AND_BACK, GL_DIFFUSE, base);
    glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, zero);
    glMaterialfv(GL_FRONT_AND_BACK, GL_EMISSION, zero);
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glEnable(GL_NORMALIZE);
    glLoadMatrixf(d.model_view);

    GLuint tex = srt::preview_texture(d);
    glTexEnvf(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    glEnable(GL_TEXTURE_2D);

    const sepal_vertex* v = d.mesh->vertices;
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_NORMAL_ARRAY);
    glEnableClientState(GL_TEXTURE_COORD_ARRAY);
    glVertexPointer(3, GL_FLOAT, sizeof(sepal_vertex), v->position);
    glNormalPointer(GL_FLOAT, sizeof(sepal_vertex), v->normal);
    glTexCoordPointer(2, GL_FLOAT, sizeof(sepal_vertex), v->uv);
    glDrawElements(GL_TRIANGLES, d.mesh->index_count, GL_UNSIGNED_SHORT, d.mesh->indices);
    const sepal_result r = gl_check("preview_gles1 draw", err);

    glDisableClientState(GL_VERTEX_ARRAY);
    glDisableClientState(GL_NORMAL_ARRAY);
    glDisableClientState(GL_TEXTURE_COORD_ARRAY);
    glDisable(GL_TEXTURE_2D);
    glDisable(GL_LIGHTING);
    glDisable(GL_LIGHT0);
    glDisable(GL_NORMALIZE);
    glDeleteTextures(1, &tex);
    return r != SEPAL_OK ? r : ok(err);
}

}  // namespace srt
