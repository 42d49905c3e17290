/* web/compat/assimp/cfileio.h -- the type meshes/mesh_internal.h embeds in mesh_io (the files assimp may read),
 * for the browser build, which has no assimp: the page reads OBJ files with web/obj.c, and the files that use
 * mesh_io (meshes/import*.c) are not part of it. */
#ifndef INSTESS_WEB_AIFILEIO_H
#define INSTESS_WEB_AIFILEIO_H

struct aiFileIO {
    void *open_proc, *close_proc, *user_data;
};

#endif
