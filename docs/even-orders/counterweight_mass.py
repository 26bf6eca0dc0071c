"""The counterweights' mass properties (docs/reference-machine.md): the FE tub's concrete sectors
(fe/src/bodies/tub.rs, `Tub::default`) integrated over their exact cylindrical geometry by
Gauss-Legendre quadrature. Usage: python3 counterweight_mass.py"""
import numpy as np
rho=2400.0; zc=0.45
def sector(r,h,xc0,xc1,thc,half=np.pi/2,n=200):
    # Gauss-Legendre in (rad, theta, x)
    gr,wr=np.polynomial.legendre.leggauss(8); gt,wt=np.polynomial.legendre.leggauss(64); gx,wx=np.polynomial.legendre.leggauss(8)
    R=r+h/2+h/2*gr; T=thc+half*gt; X=(xc0+xc1)/2+(xc1-xc0)/2*gx
    M=0; S=np.zeros(3); J=np.zeros((3,3))
    for a,wa in zip(R,wr*h/2):
        for t,wtt in zip(T,wt*half):
            for x,wxx in zip(X,wx*(xc1-xc0)/2):
                dm=rho*a*wa*wtt*wxx
                p=np.array([x,a*np.sin(t),zc+a*np.cos(t)])
                M+=dm; S+=dm*p; J+=dm*(p@p*np.eye(3)-np.outer(p,p))
    c=S/M; Jc=J-M*(c@c*np.eye(3)-np.outer(c,c))
    return M,c,Jc
xb=-0.19; dx=0.03
for name,args in [("top",(0.27,0.0212,xb+4*dx,xb+12*dx,0.0)),("bottom",(0.27,0.0166,xb+4*dx,xb+12*dx,np.pi)),("collar",(0.25,0.0229,0.17,0.30,0.0))]:
    M,c,J=sector(*args)
    np.set_printoptions(precision=5,suppress=True)
    print(name, round(M,4), c, J.tolist())
