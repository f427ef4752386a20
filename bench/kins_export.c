/* Exports the static functions of a module written by mtcal compensate --format linuxcnc-kins, for
   bench_linuxcnc_kins.cpp: compiled with -DMTCAL_KINS_STANDALONE -DMTK_MODULE="\"module.c\"" as a
   shared object and loaded with dlopen. */
#include MTK_MODULE

int mtk_export_inverse(const double world[], double L, double joints[], int *iterations, double *residual);
int mtk_export_forward(const double joints[], double L, double world[]);

int mtk_export_inverse(const double world[], double L, double joints[], int *iterations, double *residual)
{
    return mtk_inverse(world, L, joints, iterations, residual);
}

int mtk_export_forward(const double joints[], double L, double world[])
{
    return mtk_forward(joints, L, world);
}
