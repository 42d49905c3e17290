/* cli/figures.c -- `instess figures`: every figure of the three source documents into out/ (issue 4). */
#include <stdio.h>

#include "scene.h"

int scene_cmd_figures(int argc, char **argv)
{
    (void)argc, (void)argv;
    fprintf(stderr, "instess: figures: not implemented yet\n");
    return 1;
}
