# tip_arms.awk: the mean length of the arms of the particle nearest each
# crack tip of the disk (c = 1/24 m, tips at (+-c, 0)), from a run's
# particles.csv (reference positions x - ux, y - uy; sizes h): arms by the
# max rule r < 5.1 max(h_a, h_b), without those crossing the crack
# segment. doc/griffith.md uses it for L (break_length) and l_tip:
#   awk -F, -f tip_arms.awk out/small-disk/particles.csv
NR == 1 { for (k = 1; k <= NF; k++) col[$k] = k; next }
{
  n++
  X[n] = $col["x"] - $col["ux"]; Y[n] = $col["y"] - $col["uy"]; H[n] = $col["h"]
}
END {
  c = 1.0 / 24.0
  for (t = -1; t <= 1; t += 2) {
    best = -1
    for (i = 1; i <= n; i++) {
      d = (X[i] - t * c) ^ 2 + Y[i] ^ 2
      if (best < 0 || d < best) { best = d; k = i }
    }
    s = 0; m = 0
    for (i = 1; i <= n; i++) {
      if (i == k) continue
      r = sqrt((X[i] - X[k]) ^ 2 + (Y[i] - Y[k]) ^ 2)
      if (r >= 5.1 * (H[i] > H[k] ? H[i] : H[k])) continue
      if (Y[i] * Y[k] < 0) { # crosses y = 0: cut if inside the crack
        xc = X[k] + Y[k] / (Y[k] - Y[i]) * (X[i] - X[k])
        if (xc > -c && xc < c) continue
      }
      s += r; m++
    }
    printf "tip %+d: particle %d, h %.4g m, %d arms, mean length %.6g m\n", t, k - 1, H[k], m, s / m
    tot += s / m
  }
  printf "mean over both tips: %.6g m (%.4g c)\n", tot / 2, tot / 2 / c
}
