/* Drives a module written by mtcal compensate --format linuxcnc-kins as plain C (no LinuxCNC):
   compiled with -DMTCAL_KINS_STANDALONE -DMTK_MODULE="\"path/to/module.c\"". Reads lines
     I L x y z [rotary coordinates in deg]     inverse at tool length L
     F L j0 j1 ...                             forward at tool length L (LinuxCNC joint order)
     i L O x y z [rotary coordinates in deg]   inverse with G43's tool offset O (mtk_inverse_offset,
     f L O j0 j1 ...                           what kinematicsInverse/Forward call), forward likewise
   and prints per line: status, then (I, i) steps, residual and the joints, (F, f) the world
   coordinates, with 17 significant digits. */
#include MTK_MODULE
#include <stdio.h>

int main(void)
{
    char op;
    double L, O, in[MTK_N > 3 + MTK_NR ? MTK_N : 3 + MTK_NR], out[MTK_N > 3 + MTK_NR ? MTK_N : 3 + MTK_NR];
    int i, r, it;
    double res;
    while (scanf(" %c %lf", &op, &L) == 2) {
        const int inverse = op == 'I' || op == 'i';
        const int count = inverse ? 3 + MTK_NR : MTK_N;
        O = 0.0;
        if ((op == 'i' || op == 'f') && scanf("%lf", &O) != 1) return 2;
        for (i = 0; i < count; ++i)
            if (scanf("%lf", &in[i]) != 1) return 2;
        if (inverse) {
            it = 0;
            res = 0.0;
            for (i = 0; i < MTK_N; ++i) out[i] = 0.0;
            r = op == 'I' ? mtk_inverse(in, L, out, &it, &res) : mtk_inverse_offset(in, L, O, out, &it, &res);
            printf("%d %d %.17g", r, it, res);
            for (i = 0; i < MTK_N; ++i) printf(" %.17g", out[i]);
        } else {
            for (i = 0; i < 3 + MTK_NR; ++i) out[i] = 0.0;
            r = op == 'F' ? mtk_forward(in, L, out) : mtk_forward_offset(in, L, O, out);
            printf("%d", r);
            for (i = 0; i < 3 + MTK_NR; ++i) printf(" %.17g", out[i]);
        }
        printf("\n");
    }
    return 0;
}
