#pragma once
// The live page of `wearscar watch` (LiveServer): one HTML document that
// asks /state.json for what is new every half second and draws it.

namespace wearscar::app {

inline constexpr const char* kLivePage = R"HTML(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<title>wearscar watch</title>
<style>
body{font:15px/1.4 system-ui,sans-serif;margin:16px;color:#222}
h1{font-size:20px;margin:0 0 4px}
#status{color:#555;margin-bottom:8px}
.grid{display:grid;grid-template-columns:repeat(auto-fit,minmax(560px,1fr));gap:12px}
figure{margin:0;border:1px solid #ddd;padding:6px}
figcaption{font-weight:600;margin-bottom:4px}
canvas{width:100%;height:300px}
#alerts li{margin:2px 0}
.alert-steady{color:#a60}.alert-verdict{color:#b30}.alert-depth{color:#b30}
.alert-idle{color:#555}.alert-periodic{color:#b30}.alert-restart{color:#a60}
#alerts li.good{color:#0a6}
</style></head><body>
<h1>wearscar watch</h1>
<div id="status">waiting for the first cycle</div>
<div id="verdict"></div>
<div class="grid">
<figure><figcaption>mu-hat (k from P, 95% band) and the classic COF (mean method) per cycle</figcaption><canvas id="mu"></canvas></figure>
<figure><figcaption>Latest cycle: Q against x, and the wear-scar model Q = P (k + s mu-hat)/(1 - s mu-hat k)</figcaption><canvas id="loop"></canvas></figure>
<figure><figcaption>Apparent friction |Q|/P along the stroke (x, mm) per cycle (down)</figcaption><canvas id="map"></canvas></figure>
<figure><figcaption>Track depth from the spring (P/S peak to valley), mm, per cycle</figcaption><canvas id="depth"></canvas></figure>
<figure><figcaption>The track's history from the spring: P/S along the stroke (x, mm) relative to its mean, per cycle (down)</figcaption><canvas id="track"></canvas></figure>
</div>
<h2>Alerts</h2><ul id="alerts"></ul>
<script>
const S={cycles:[],updates:0,state:null};
function setup(c){const r=window.devicePixelRatio||1;const w=c.clientWidth,h=c.clientHeight;
 if(c.width!==w*r){c.width=w*r;c.height=h*r;}const g=c.getContext('2d');g.setTransform(r,0,0,r,0,0);
 g.clearRect(0,0,w,h);g.font='12px sans-serif';return [g,w,h];}
function range(vs){let lo=Infinity,hi=-Infinity;for(const v of vs){if(v==null)continue;if(v<lo)lo=v;if(v>hi)hi=v;}
 if(!(hi>lo)){lo=(isFinite(lo)?lo:0)-1;hi=lo+2;}const p=0.05*(hi-lo);return [lo-p,hi+p];}
function ticks(r){const raw=(r[1]-r[0])/4,m=Math.pow(10,Math.floor(Math.log10(raw))),f=raw/m;
 const step=(f<1.5?1:f<3.5?2:f<7.5?5:10)*m,p=Math.max(0,-Math.floor(Math.log10(step)+1e-9)),out=[];
 for(let v=Math.ceil(r[0]/step)*step;v<=r[1]+1e-9*step;v+=step)out.push([v,(Math.abs(v)<step/2?0:v).toFixed(p)]);return out;}
function axes(g,w,h,xr,yr,xl,yl){const L=56,B=28;g.strokeStyle='#888';g.beginPath();g.moveTo(L,4);g.lineTo(L,h-B);g.lineTo(w-4,h-B);g.stroke();
 const X=x=>L+(x-xr[0])/(xr[1]-xr[0])*(w-L-4),Y=y=>h-B-(y-yr[0])/(yr[1]-yr[0])*(h-B-4);
 g.fillStyle='#333';for(const [v,t] of ticks(yr)){const py=Y(v);g.fillText(t,L-6-g.measureText(t).width,py+4);g.fillRect(L-3,py,3,1);}
 for(const [v,t] of ticks(xr)){const px=X(v),tw=g.measureText(t).width;g.fillText(t,Math.min(Math.max(px-tw/2,L),w-4-tw),h-B+14);g.fillRect(px,h-B,1,3);}
 g.fillText(xl,w/2-g.measureText(xl).width/2,h-2);g.fillText(yl,L+6,14);
 return [X,Y];}
function line(g,X,Y,xs,ys,color){g.strokeStyle=color;g.beginPath();let on=false;for(let i=0;i<xs.length;i++){
 if(ys[i]==null||xs[i]==null){on=false;continue;}const px=X(xs[i]),py=Y(ys[i]);if(on)g.lineTo(px,py);else g.moveTo(px,py);on=true;}g.stroke();}
function drawMu(){const [g,w,h]=setup(document.getElementById('mu'));const c=S.cycles;if(!c.length)return;
 const x=c.map(r=>r[0]);const yr=range(c.flatMap(r=>[r[2],r[3],r[4]]));const [X,Y]=axes(g,w,h,range(x),yr,'cycle','mu');
 g.fillStyle='rgba(30,100,200,0.15)';g.beginPath();c.forEach((r,i)=>{if(r[2]!=null)(i?g.lineTo:g.moveTo).call(g,X(r[0]),Y(r[2]));});
 for(let i=c.length-1;i>=0;i--)if(c[i][3]!=null)g.lineTo(X(c[i][0]),Y(c[i][3]));g.fill();
 line(g,X,Y,x,c.map(r=>r[1]),'#1e64c8');line(g,X,Y,x,c.map(r=>r[4]),'#c8501e');
 g.fillStyle='#1e64c8';g.fillText('mu-hat',w-150,16);g.fillStyle='#c8501e';g.fillText('COF (mean)',w-90,16);}
function drawLoop(st){const [g,w,h]=setup(document.getElementById('loop'));const l=st.loop;if(!l||!l.x.length)return;
 const [X,Y]=axes(g,w,h,range(l.x),range(l.q.concat(l.model)),'x, mm (cycle '+l.cycle+')','Q, N');
 g.fillStyle='rgba(80,80,80,0.5)';for(let i=0;i<l.x.length;i++)if(l.q[i]!=null)g.fillRect(X(l.x[i])-1,Y(l.q[i])-1,2,2);
 g.fillStyle='#c00';for(let i=0;i<l.x.length;i++)if(l.model[i]!=null)g.fillRect(X(l.x[i])-0.75,Y(l.model[i])-0.75,1.5,1.5);
 g.fillStyle='#555';g.fillText('measured',w-150,16);g.fillStyle='#c00';g.fillText('model',w-80,16);}
function drawMap(st,id,key,label,unit){const [g,w,h]=setup(document.getElementById(id));const m=st.map;if(!m||!m[key]||!m[key].length)return;
 const rows=m[key];const vs=rows.flat().filter(v=>v!=null).sort((a,b)=>a-b);const lo=vs[Math.floor(0.02*vs.length)]||0,hi=vs[Math.floor(0.98*vs.length)]||1;
 const L=56,B=28,cw=(w-L-4)/m.x.length,rh=(h-B-4)/rows.length;
 rows.forEach((r,j)=>r.forEach((v,i)=>{if(v==null)return;const t=Math.max(0,Math.min(1,(v-lo)/((hi-lo)||1)));
  g.fillStyle='hsl('+(240-240*t)+',80%,50%)';g.fillRect(L+i*cw,4+j*rh,Math.ceil(cw),Math.ceil(rh));}));
 g.fillStyle='#333';g.fillText(m.x[0].toFixed(2),L,h-B+14);g.fillText(m.x[m.x.length-1].toFixed(2),w-40,h-B+14);
 g.fillText('cycle '+m.first[0],2,14);g.fillText(''+m.last[m.last.length-1],2,h-B);
 g.fillText(label+' '+lo.toFixed(unit)+' (blue) to '+hi.toFixed(unit)+' (red)',L+4,h-4);}
function drawDepth(){const [g,w,h]=setup(document.getElementById('depth'));const c=S.cycles;if(!c.length)return;
 const x=c.map(r=>r[0]),y=c.map(r=>r[7]);const [X,Y]=axes(g,w,h,range(x),range(y),'cycle','depth, mm');line(g,X,Y,x,y,'#264');}
async function poll(){try{const r=await fetch('state.json?since='+S.cycles.length,{cache:'no-store'});const st=await r.json();
 if(S.state&&st.restarts!==S.state.restarts)S.cycles=[];
 S.cycles=S.cycles.concat(st.cycles);S.state=st;S.updates++;const last=S.cycles[S.cycles.length-1];
 const b=document.body.dataset;b.updates=S.updates;b.cyclesSeen=(b.cyclesSeen?b.cyclesSeen+',':'')+S.cycles.length;
 document.getElementById('status').textContent='cycles: '+S.cycles.length+' · updates: '+S.updates+(last?' · mu-hat '+(last[1]==null?'-':last[1].toFixed(4))+' · COF '+last[4].toFixed(4):'')+(st.steady?' · steady':'');
 document.getElementById('verdict').textContent=st.verdict?'verdict '+st.verdict:'';
 const ul=document.getElementById('alerts');ul.innerHTML='';
 st.events.slice().reverse().forEach(e=>{const li=document.createElement('li');li.className='alert-'+e.kind+(e.good?' good':'');li.textContent='cycle '+e.cycle+' · '+e.kind+': '+e.message;ul.appendChild(li);});
 drawMu();drawLoop(st);drawMap(st,'map','rows','|Q|/P',3);drawDepth();drawMap(st,'track','track','P/S, mm',4);}catch(e){document.getElementById('status').textContent='the watch has ended or is not reachable ('+e+')';}
 setTimeout(poll,500);}
poll();
</script></body></html>)HTML";

}  // namespace wearscar::app
