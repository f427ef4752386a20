/* Drives the simulated-probe component written by mtcal linuxcnc-probe as plain C (no LinuxCNC):
   compiled with -DMTCAL_PROBE_STANDALONE -DMTP_MODULE="\"path/to/mtcal_probe.c\"". Reads lines
     L j0 j1 ...    tool length L, joints in LinuxCNC joint order (mm, deg)
   and prints per line: status, gap (mm), sphere, tip x y z, with 17 significant digits. */
#include MTP_MODULE
#include <stdio.h>

int main(void)
{
    double L, j[MTK_N], tip[3], gap;
    int i, r, sphere;
    while (scanf("%lf", &L) == 1) {
        for (i = 0; i < MTK_N; ++i)
            if (scanf("%lf", &j[i]) != 1) return 2;
        tip[0] = tip[1] = tip[2] = 0.0;
        gap = 0.0;
        sphere = -1;
        r = mtp_gap(j, L, &gap, &sphere, tip);
        printf("%d %.17g %d %.17g %.17g %.17g\n", r, gap, sphere, tip[0], tip[1], tip[2]);
    }
    return 0;
}
