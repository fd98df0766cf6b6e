# Writes data/prototype_cube_m1_n5.txt: V, K, D of the reference numpy prototype
# (elas.py of the SGBEM prototype that came with the project's reference material; it is not part of
# this repository) on the 12-triangle unit cube with n = 5.
# Run (Debian python3 with numpy) in the prototype's folder: /usr/bin/python3 <this file> <output path>
import sys
import numpy as np
sys.path.insert(0, '.')
import elas
from elas import cube_mesh, build_ops, tri_data, kelvin
from ss import ss_rule, reg_rule

def assemble(X, T, nreg, nsing):
    # elas.assemble with one change: the shared edge of a touching pair is ordered as in the
    # lower-numbered triangle, so that pairs (a,b) and (b,a) use the same quadrature points
    # (crackflow computes each unordered pair once), and that triangle takes the x role of the rule.
    Mt = len(T)
    td = tri_data(X, T)
    I1 = np.zeros((Mt, Mt)); IU = np.zeros((Mt, Mt, 3, 3)); IK = np.zeros((Mt, Mt, 3))
    rules = {c: ss_rule(nsing, c) for c in ['id', 'edge', 'vert']}
    rules['reg'] = reg_rule(nreg)
    sets = [set(t) for t in T]
    for a in range(Mt):
        for b in range(Mt):
            sh = [v for v in T[min(a, b)] if v in sets[max(a, b)]]
            ta = list(T[a]); tb = list(T[b])
            if len(sh) == 3: case = 'id'; tb = ta[:]
            elif len(sh) == 2:
                case = 'edge'
                o_a = [v for v in ta if v not in sh][0]; o_b = [v for v in tb if v not in sh][0]
                ta = [sh[0], sh[1], o_a]; tb = [sh[0], sh[1], o_b]
            elif len(sh) == 1:
                case = 'vert'
                ta = [sh[0]] + [v for v in ta if v != sh[0]]; tb = [sh[0]] + [v for v in tb if v != sh[0]]
            else: case = 'reg'
            P, Q, W = rules[case]
            if a > b: P, Q = Q, P  # the lower-numbered triangle takes the rule's x role
            A = X[ta]; B = X[tb]
            x = A[0] + P[:, :1]*(A[1]-A[0]) + P[:, 1:]*(A[2]-A[0])
            y = B[0] + Q[:, :1]*(B[1]-B[0]) + Q[:, 1:]*(B[2]-B[0])
            w = W*4*td[a]['area']*td[b]['area']
            d = x - y
            Uk, r = kelvin(d)
            I1[a, b] = np.sum(w/r)
            IU[a, b] = np.einsum('q,qij->ij', w, Uk)
            lamb = np.stack([1-Q[:, 0]-Q[:, 1], Q[:, 0], Q[:, 1]], 1)
            kd = (d @ td[b]['n'])/r**3
            vals = np.einsum('q,qk->k', w*kd, lamb)
            for k, v in enumerate(tb):
                IK[a, b, list(T[b]).index(v)] = vals[k]
    return td, I1, IU, IK

X, T = cube_mesh(1)
td, I1, IU, IK = assemble(X, T, nreg=5, nsing=5)
V, K, D, M01 = build_ops(X, T, td, I1, IU, IK)
with open(sys.argv[1], 'w') as f:
    f.write('%d %d\n' % (len(X), len(T)))
    for p in X: f.write('%.17g %.17g %.17g\n' % tuple(p))
    for t in T: f.write('%d %d %d\n' % tuple(t))
    for A in (V, K, D):
        for row in A: f.write(' '.join('%.17g' % x for x in row) + '\n')
