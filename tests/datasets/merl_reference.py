"""The published MERL reader (BRDFRead.cpp, Matusik et al. 2003), transcribed line by
line into scalar Python: an implementation independent of app/datasets/merl.py."""
import math

RES_THETA_H, RES_THETA_D, RES_PHI_D = 90, 90, 360
SCALES = (1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def rotate_vector(vector, axis, angle):
    cos_ang, sin_ang = math.cos(angle), math.sin(angle)
    out = [vector[i] * cos_ang for i in range(3)]
    temp = sum(axis[i] * vector[i] for i in range(3)) * (1.0 - cos_ang)
    out = [out[i] + axis[i] * temp for i in range(3)]
    c = cross(axis, vector)
    return [out[i] + c[i] * sin_ang for i in range(3)]


def std_coords_to_half_diff_coords(theta_in, fi_in, theta_out, fi_out):
    in_vec = (math.sin(theta_in) * math.cos(fi_in), math.sin(theta_in) * math.sin(fi_in), math.cos(theta_in))
    out_vec = (math.sin(theta_out) * math.cos(fi_out), math.sin(theta_out) * math.sin(fi_out), math.cos(theta_out))
    half = [(in_vec[i] + out_vec[i]) / 2.0 for i in range(3)]
    norm = math.sqrt(sum(x * x for x in half))
    half = [x / norm for x in half]
    theta_half = math.acos(half[2])
    fi_half = math.atan2(half[1], half[0])
    temp = rotate_vector(in_vec, (0.0, 0.0, 1.0), -fi_half)
    diff = rotate_vector(temp, (0.0, 1.0, 0.0), -theta_half)
    return theta_half, fi_half, math.acos(diff[2]), math.atan2(diff[1], diff[0])


def theta_half_index(theta_half):
    if theta_half <= 0.0:
        return 0
    theta_half_deg = (theta_half / (math.pi / 2.0)) * RES_THETA_H
    ret = int(math.sqrt(theta_half_deg * RES_THETA_H))
    return min(max(ret, 0), RES_THETA_H - 1)


def theta_diff_index(theta_diff):
    tmp = int(theta_diff / (math.pi * 0.5) * RES_THETA_D)
    return min(max(tmp, 0), RES_THETA_D - 1)


def phi_diff_index(phi_diff):
    if phi_diff < 0.0:
        phi_diff += math.pi
    tmp = int(phi_diff / math.pi * RES_PHI_D / 2)
    return min(max(tmp, 0), RES_PHI_D // 2 - 1)


def lookup_brdf_val(brdf, theta_in, fi_in, theta_out, fi_out):
    """(r, g, b) from the flat list of 3·90·90·180 stored doubles."""
    theta_half, _, theta_diff, fi_diff = std_coords_to_half_diff_coords(theta_in, fi_in, theta_out, fi_out)
    ind = (phi_diff_index(fi_diff) + theta_diff_index(theta_diff) * RES_PHI_D // 2
           + theta_half_index(theta_half) * RES_PHI_D // 2 * RES_THETA_D)
    n = RES_THETA_H * RES_THETA_D * RES_PHI_D // 2
    return (brdf[ind] * SCALES[0], brdf[ind + n] * SCALES[1], brdf[ind + 2 * n] * SCALES[2])
