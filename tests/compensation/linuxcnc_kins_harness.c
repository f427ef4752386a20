/* Drives a module written by mtcal compensate --format linuxcnc-kins as plain C (no LinuxCNC):
   compiled with -DMTCAL_KINS_STANDALONE -DMTK_MODULE="\"path/to/module.c\"". Reads lines
     I L x y z [rotary coordinates in deg]   inverse at tool length L
     F L j0 j1 ...                           forward at tool length L (LinuxCNC joint order)
   and prints per line: status, then (I) steps, residual and the joints, (F) the world coordinates,
   with 17 significant digits. */
#include MTK_MODULE
#include <stdio.h>

int main(void)
{
    char op;
    double L, in[MTK_N > 3 + MTK_NR ? MTK_N : 3 + MTK_NR], out[MTK_N > 3 + MTK_NR ? MTK_N : 3 + MTK_NR];
    int i, r, it;
    double res;
    while (scanf(" %c %lf", &op, &L) == 2) {
        const int count = op == 'I' ? 3 + MTK_NR : MTK_N;
        for (i = 0; i < count; ++i)
            if (scanf("%lf", &in[i]) != 1) return 2;
        if (op == 'I') {
            it = 0;
            res = 0.0;
            for (i = 0; i < MTK_N; ++i) out[i] = 0.0;
            r = mtk_inverse(in, L, out, &it, &res);
            printf("%d %d %.17g", r, it, res);
            for (i = 0; i < MTK_N; ++i) printf(" %.17g", out[i]);
        } else {
            for (i = 0; i < 3 + MTK_NR; ++i) out[i] = 0.0;
            r = mtk_forward(in, L, out);
            printf("%d", r);
            for (i = 0; i < 3 + MTK_NR; ++i) printf(" %.17g", out[i]);
        }
        printf("\n");
    }
    return 0;
}
