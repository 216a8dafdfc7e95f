/*
 * report.js: the HTML report's script (report_html.c): the 3D view of the restored part
 * and its patches on a 2D canvas (painter's order, flat shading, rotate by dragging,
 * zoom by the wheel) and the outlines of the selected layer as SVG with the build plans
 * over them, from the page's JSON data block. Plain ES5, no external anything.
 * Compiled into the binary by the Makefile (report_assets.h), this opening comment left
 * out, every line as it is.
 */
(function(){'use strict';
var data=JSON.parse(document.getElementById('report-data').textContent);
var cv=document.getElementById('view');
var sp=document.getElementById('show-part'),sq=document.getElementById('show-patches');
var meshes=[];
if(data.restored)meshes.push({m:data.restored,col:[168,176,188],patch:false});
data.patches.forEach(function(p){meshes.push({m:p,col:[232,96,28],patch:true});});
var lo=[Infinity,Infinity,Infinity],hi=[-Infinity,-Infinity,-Infinity];
meshes.forEach(function(e){var v=e.m.v;for(var i=0;i<v.length;i+=3)for(var k=0;k<3;k++){if(v[i+k]<lo[k])lo[k]=v[i+k];if(v[i+k]>hi[k])hi[k]=v[i+k];}});
var ctr=[(lo[0]+hi[0])/2,(lo[1]+hi[1])/2,(lo[2]+hi[2])/2];
var rad=Math.max(1e-9,Math.sqrt(Math.pow(hi[0]-lo[0],2)+Math.pow(hi[1]-lo[1],2)+Math.pow(hi[2]-lo[2],2))/2);
var yaw=0.6,pitch=0.45,zoom=1,pending=false;
function draw(){pending=false;if(!cv||!cv.getContext)return;var g=cv.getContext('2d');
 var W=cv.width,H=cv.height;g.fillStyle='#ffffff';g.fillRect(0,0,W,H);
 if(!meshes.length){g.fillStyle='#5b6673';g.font='16px sans-serif';g.fillText('no meshes stored with this run',20,40);return;}
 var cy=Math.cos(yaw),sy=Math.sin(yaw),cp=Math.cos(pitch),spn=Math.sin(pitch);
 var s=zoom*0.45*Math.min(W,H)/rad;var faces=[];
 meshes.forEach(function(e){if(e.patch?(sq&&!sq.checked):(sp&&!sp.checked))return;
  var v=e.m.v,t=e.m.t,n=v.length/3,P=new Float64Array(v.length);
  for(var i=0;i<n;i++){var x=v[3*i]-ctr[0],y=v[3*i+1]-ctr[1],z=v[3*i+2]-ctr[2];
   var x1=cy*x-sy*y,y1=sy*x+cy*y;P[3*i]=x1;P[3*i+1]=cp*y1-spn*z;P[3*i+2]=spn*y1+cp*z;}
  var bias=e.patch?-4*rad:0;
  for(var j=0;j<t.length;j+=3){var a=3*t[j],b=3*t[j+1],c=3*t[j+2];
   var ux=P[b]-P[a],uy=P[b+1]-P[a+1],uz=P[b+2]-P[a+2],vx=P[c]-P[a],vy=P[c+1]-P[a+1],vz=P[c+2]-P[a+2];
   var nx=uy*vz-uz*vy,ny=uz*vx-ux*vz,nz=ux*vy-uy*vx,nl=Math.sqrt(nx*nx+ny*ny+nz*nz);
   if(!(nl>0))continue;var lum=0.35+0.65*Math.abs(ny)/nl;
   faces.push({d:(P[a+1]+P[b+1]+P[c+1])/3+bias,P:P,a:a,b:b,c:c,col:e.col,lum:lum});}});
 faces.sort(function(p,q){return q.d-p.d;});
 for(var f=0;f<faces.length;f++){var F=faces[f],P=F.P;
  var col='rgb('+Math.round(F.col[0]*F.lum)+','+Math.round(F.col[1]*F.lum)+','+Math.round(F.col[2]*F.lum)+')';g.fillStyle=col;g.strokeStyle=col;g.lineWidth=0.6;
  g.beginPath();g.moveTo(W/2+s*P[F.a],H/2-s*P[F.a+2]);g.lineTo(W/2+s*P[F.b],H/2-s*P[F.b+2]);g.lineTo(W/2+s*P[F.c],H/2-s*P[F.c+2]);g.closePath();g.fill();g.stroke();}
}
function later(){if(!pending){pending=true;window.requestAnimationFrame(draw);}}
if(cv){var drag=null;
 cv.addEventListener('pointerdown',function(ev){drag=[ev.clientX,ev.clientY];cv.setPointerCapture(ev.pointerId);});
 cv.addEventListener('pointermove',function(ev){if(!drag)return;yaw+=(ev.clientX-drag[0])*0.01;pitch+=(ev.clientY-drag[1])*0.01;drag=[ev.clientX,ev.clientY];later();});
 cv.addEventListener('pointerup',function(){drag=null;});
 cv.addEventListener('wheel',function(ev){ev.preventDefault();zoom*=ev.deltaY<0?1.1:1/1.1;later();},{passive:false});}
if(sp)sp.addEventListener('change',later);if(sq)sq.addEventListener('change',later);
var rs=document.getElementById('reset-view');if(rs)rs.addEventListener('click',function(){yaw=0.6;pitch=0.45;zoom=1;later();});
draw();
var sel=document.getElementById('layer-select'),plot=document.getElementById('layer-plot');
var zb=document.getElementById('plot-zoom');
var L=data.layers,ex=[Infinity,Infinity,-Infinity,-Infinity];
function grow(a){for(var i=0;i+1<a.length;i+=2){if(a[i]===null||a[i+1]===null)continue;if(a[i]<ex[0])ex[0]=a[i];if(a[i+1]<ex[1])ex[1]=a[i+1];if(a[i]>ex[2])ex[2]=a[i];if(a[i+1]>ex[3])ex[3]=a[i+1];}}
L.forEach(function(l){grow(l.d);grow(l.r);});
var PL=data.plans||[];
PL.forEach(function(p){p.layers.forEach(function(q){q.g.forEach(grow);});});
function planLayers(i){var out=[];PL.forEach(function(p){p.layers.forEach(function(q,k){if(i>=q.rf&&i<=q.rl)out.push({p:p,q:q,k:k});});});return out;}
function area(c,S,cls){var d='';c.forEach(function(a){if(a.length<6)return;d+='M';for(var j=0;j+1<a.length;j+=2)d+=(j?' L':'')+fmt(S.x(a[j]))+' '+fmt(S.y(a[j+1]));d+=' Z ';});return d?'<path class="'+cls+'" d="'+d+'"/>':'';}
function path(a,S,cls){var pts=[];for(var j=0;j+1<a.length;j+=2)pts.push(fmt(S.x(a[j]))+','+fmt(S.y(a[j+1])));return pts.length>1?'<polyline class="'+cls+'" points="'+pts.join(' ')+'"/>':'';}
function fmt(x){return (Math.round(x*1000)/1000).toString();}
function lines(a,S,cls){var n=a.length/2,out='',cur=[];
 function flush(){if(cur.length>1)out+='<polyline class="'+cls+'" points="'+cur.join(' ')+'"/>';cur=[];}
 for(var i=0;i<=n&&n>0;i++){var k=i%n,x=a[2*k],y=a[2*k+1];if(x===null||y===null){flush();continue;}cur.push(fmt(S.x(x))+','+fmt(S.y(y)));}
 flush();return out;}
function plotLayer(){if(!plot)return;if(!L.length||!(ex[2]>=ex[0])){plot.innerHTML='<p class="note">no per-layer outlines stored with this run</p>';return;}
 var i=sel?parseInt(sel.value,10):0;if(!(i>=0&&i<L.length))i=0;var l=L[i];
 var pls=planLayers(i),plan='',np=0,E=ex,zoomed=false;
 if(zb&&zb.checked&&pls.length){var z=[Infinity,Infinity,-Infinity,-Infinity];
  pls.forEach(function(e){e.q.g.forEach(function(a){for(var j=0;j+1<a.length;j+=2){if(a[j]<z[0])z[0]=a[j];if(a[j+1]<z[1])z[1]=a[j+1];if(a[j]>z[2])z[2]=a[j];if(a[j+1]>z[3])z[3]=a[j+1];}});});
  if(z[2]>=z[0]){var g=0.15*Math.max(z[2]-z[0],z[3]-z[1])+1;E=[z[0]-g,z[1]-g,z[2]+g,z[3]+g];zoomed=true;}}
 var W=640,H=640,m=30,span=Math.max(E[2]-E[0],E[3]-E[1],1e-9),k=(W-2*m)/span;
 var x0=(E[0]+E[2]-span)/2,y0=(E[1]+E[3]-span)/2;
 var S={x:function(x){return m+(x-x0)*k;},y:function(y){return H-m-(y-y0)*k;}};
 pls.forEach(function(e){plan+=area(e.q.m,S,'mr')+area(e.q.g,S,'gr');});
 pls.forEach(function(e){e.q.paths.forEach(function(t){var s=path(t.p,S,t.k===1?'tp ring':'tp raster');if(s){plan+=s;np++;}});});
 var cap=pls.length?pls.map(function(e){return 'section '+e.p.section+' plan layer '+(e.k+1)+'/'+e.p.layers.length;}).join(', ')+': '+np+' paths':'no build plan in this layer';
 var svg='<svg viewBox="0 0 '+W+' '+H+'" width="'+W+'" height="'+H+'" role="img">'+'<style>.dm{fill:none;stroke:#b3261e;stroke-width:2}.rs{fill:none;stroke:#1f5fbf;stroke-width:1.5;stroke-dasharray:6 4}.mr{fill:#f6b26b;fill-opacity:.45;stroke:none;fill-rule:nonzero}.gr{fill:none;stroke:#8a5a00;stroke-width:1;stroke-dasharray:3 3}.tp{fill:none;stroke-width:1.2}.ring{stroke:#0b7a3e}.raster{stroke:#6a1b9a}</style>'+plan+lines(l.r,S,'rs')+lines(l.d,S,'dm')+'<rect x="0" y="0" width="'+W+'" height="44" fill="#fff" fill-opacity=".85"/>'+'<text x="'+m+'" y="20" font-size="13">layer '+i+', z = '+fmt(l.z)+' mm (aligned frame; '+fmt(span)+' mm across'+(zoomed?', zoomed to the build plan':'')+')</text>'+'<text x="'+m+'" y="38" font-size="12" class="plan-caption">'+cap+'</text>'+'</svg>';
 plot.innerHTML=svg;plot.setAttribute('data-paths',String(np));}
if(sel)sel.addEventListener('change',plotLayer);if(zb)zb.addEventListener('change',plotLayer);plotLayer();
document.body.setAttribute('data-rendered','1');
})();
