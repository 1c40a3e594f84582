#!/usr/bin/python3
# a1_series.py -- derivation aid (not part of the build): the exact second-order expansion of a
# refraction (argv[1] = refr) or reflection (refl) at a surface w = 1/2 u^T Q u + 1/6 c[u,u,u] in the
# paper frames, by truncated power series in sympy (Debian python3-sympy). Writes a pickle used by
# a1_check.py, which compares it with the closed form in libparaxial/src/bounds.c.
# Usage: /usr/bin/python3 a1_series.py refr 2 && /usr/bin/python3 a1_check.py refr
import sympy as sp, sys, pickle
ORDER=int(sys.argv[2]) if len(sys.argv)>2 else 2
refl = sys.argv[1]=='refl'
e=sp.symbols('epsilon')
X1,X2,k1,k2=sp.symbols('X1 X2 k1 k2',real=True)
S,C,eta,Cp=sp.symbols('S C eta Cp',real=True)
q11,q12,q22=sp.symbols('q11 q12 q22',real=True)
c111,c112,c122,c222=sp.symbols('c111 c112 c122 c222',real=True)
def tr(p):  # truncate polynomial in e
    p=sp.expand(p)
    return sum(p.coeff(e,k)*e**k for k in range(ORDER+1))
def mul(a,b): return tr(sp.expand(a)*sp.expand(b))
def inv(a):
    a=sp.expand(a); a0=a.coeff(e,0); r=tr((a-a0)/a0)
    s=1; rk=1
    for k in range(1,ORDER+1):
        rk=mul(rk,r); s+= (-1)**k*rk
    return tr(s/a0)
def sqrt_(a):
    a=sp.expand(a); a0=a.coeff(e,0); r=tr((a-a0)/a0)
    coef=[1,sp.Rational(1,2),-sp.Rational(1,8),sp.Rational(1,16),-sp.Rational(5,128)]
    s=1; rk=1
    for k in range(1,ORDER+1):
        rk=mul(rk,r); s+=coef[k]*rk
    return tr(sp.sqrt(a0)*s)
def dot(a,b): return tr(sum(mul(x,y) for x,y in zip(a,b)))
def f(u1,u2):
    return tr(sp.Rational(1,2)*(q11*mul(u1,u1)+2*q12*mul(u1,u2)+q22*mul(u2,u2))
              +sp.Rational(1,6)*(c111*mul(u1,mul(u1,u1))+3*c112*mul(mul(u1,u1),u2)+3*c122*mul(u1,mul(u2,u2))+c222*mul(u2,mul(u2,u2))))
def grad(u1,u2):
    g1=q11*u1+q12*u2+sp.Rational(1,2)*(c111*mul(u1,u1)+2*c112*mul(u1,u2)+c122*mul(u2,u2))
    g2=q12*u1+q22*u2+sp.Rational(1,2)*(c112*mul(u1,u1)+2*c122*mul(u1,u2)+c222*mul(u2,u2))
    return tr(g1),tr(g2)
x1=[C,0,-S]; x2=[0,1,0]; s=[S,0,C]
a=k1*e; b=k2*e
zeta=sqrt_(1-a**2-b**2)
d=[tr(a*x1[i]+b*x2[i]+zeta*s[i]) for i in range(3)]
o=[X1*e*x1[i]+X2*e*x2[i] for i in range(3)]
ts=sp.symbols('t1:%d'%(ORDER+1))
t=sum(ts[k]*e**(k+1) for k in range(ORDER))
p=[tr(o[i]+mul(t,d[i])) for i in range(3)]
eq=tr(p[2]-f(p[0],p[1]))
sol={}
for k in range(1,ORDER+1):
    ck=sp.expand(eq.coeff(e,k).subs(sol))
    sol[ts[k-1]]=sp.solve(ck,ts[k-1])[0]
P=[tr(pi.subs(sol)) for pi in p]
g1,g2=grad(P[0],P[1])
Nraw=[-g1,-g2,sp.Integer(1)]
nn=inv(sqrt_(dot(Nraw,Nraw)))
N=[mul(c,nn) for c in Nraw]
ci=dot(d,N)
if refl:
    dp=[tr(d[i]-2*mul(ci,N[i])) for i in range(3)]
    Sp=S; Cpv=-C
else:
    # cos' = sqrt(1 - eta^2 (1 - ci^2)); at e=0 equals Cp
    arg=tr(1-eta**2*(1-mul(ci,ci)))
    arg0=sp.expand(arg.coeff(e,0)); r=tr((arg-arg0)/ (Cp**2))
    coef=[1,sp.Rational(1,2),-sp.Rational(1,8),sp.Rational(1,16)]
    sq=1; rk=1
    for k in range(1,ORDER+1):
        rk=mul(rk,r); sq+=coef[k]*rk
    cpp=tr(Cp*sq)
    dp=[tr(eta*d[i]+mul(cpp-eta*ci,N[i])) for i in range(3)]
    Sp=eta*S; Cpv=Cp
spv=[Sp,0,Cpv]; x1p=[Cpv,0,-Sp]
tp=mul(-dot(P,spv),inv(dot(dp,spv)))
Q=[tr(P[i]+mul(tp,dp[i])) for i in range(3)]
out=[dot(Q,x1p),dot(Q,x2),dot(dp,x1p),dot(dp,x2)]
res={}
for i,oi in enumerate(out):
    for k in range(1,ORDER+1):
        ck=sp.expand(oi.coeff(e,k))
        if not refl: ck=ck.subs(Cp**2,1-eta**2*S**2)
        ck=sp.factor(sp.simplify(ck)) if k<3 else ck
        res[(i,k)]=ck
        if k<3: print(i,k,ck,flush=True)
pickle.dump(res,open('a1_series_%s_%d.pkl'%(sys.argv[1],ORDER),'wb'))
